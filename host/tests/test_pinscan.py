"""The pin scanner (host/rig/scan/pinscan.py) on firmware written as public MicroPython drivers and
robots write it, `mpy-fil check`'s comparison of the code's pins with the wiring, and
`mpy-fil init`'s names and bridge guess (host/rig/scan/starter.py)."""

import ast
import shutil

import pytest

from host import cli
from host.core.paths import REPO
from host.rig.config.boardfile import apps_of
from host.rig.config.rigfile import load_rig
from host.rig.scan.pincheck import check_pins
from host.rig.scan.pinscan import scan_folder, scan_modules
from host.rig.scan.starter import starter


def pins(files: dict[str, str], family=None) -> dict[str, str | None]:
    """key -> the code's name for it, of every pin the modules make."""
    modules = {name: (f"{name}.py", ast.parse(source)) for name, source in files.items()}
    return {use.key: use.name for use in scan_modules(modules, list(modules), family).uses}


def scan(files: dict[str, str], family=None):
    modules = {name: (f"{name}.py", ast.parse(source)) for name, source in files.items()}
    return scan_modules(modules, list(modules), family)


# -- the scanner ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    "source",
    [
        "from machine import Pin\necho = Pin(18, Pin.IN)\n",
        "import machine\necho = machine.Pin(18, machine.Pin.IN, machine.Pin.PULL_DOWN)\n",
        "from machine import Pin\necho = Pin(id=18, mode=Pin.IN)\n",
        "from machine import Pin\nclass S:\n    def __init__(self):\n        self.echo = Pin(18, Pin.IN)\n",
        "from machine import Pin as GPIO\necho = GPIO(18, GPIO.IN)\n",
        "import machine as m\necho = m.Pin(18, m.Pin.IN)\n",
    ],
)
def test_a_literal_pin_in_every_way_code_makes_one(source):
    assert pins({"main": source}) == {"18": "echo"}


@pytest.mark.parametrize(
    "files",
    [
        {"main": "from machine import Pin\nfrom micropython import const\nECHO = const(18)\nPin(ECHO, Pin.IN)\n"},
        {"main": "from machine import Pin\nECHO = 18\ndef setup():\n    return Pin(ECHO)\n"},
        {"main": "from machine import Pin\nTRIG, ECHO = 17, 18\nPin(ECHO)\n"},
        {"config": "ECHO = 18\n", "main": "import config\nfrom machine import Pin\nPin(config.ECHO)\n"},
        {"config": "ECHO = 18\n", "main": "from config import ECHO\nfrom machine import Pin\nPin(ECHO)\n"},
        {"board": "from micropython import const\nECHO = const(18)\n", "main": "from board import *\nPin(ECHO)\n"},
        {"board": "BASE = 16\nECHO = BASE + 2\n", "main": "import board as b\nfrom machine import Pin\nPin(b.ECHO)\n"},
    ],
)
def test_a_pin_by_its_constant_here_or_in_a_module_it_imports(files):
    assert pins(files) == {"18": "ECHO"}


def test_pwm_adc_and_uart_and_the_rp2040_adc_channels():
    source = (
        "from machine import Pin, PWM, ADC, UART\n"
        "pwm = PWM(Pin(15), freq=1000)\n"
        "a = ADC(Pin(27))\n"
        "b = ADC(0)\n"
        "t = ADC(4)\n"  # the RP2040's temperature sensor: no pin
        "u = UART(1, baudrate=9600, tx=Pin(4), rx=5)\n"
    )
    found = scan({"main": source}, family="rp2").uses
    shown = {(u.key, u.call, u.kind) for u in found}
    assert shown == {
        ("15", "PWM(Pin(15))", "pwm"),
        ("27", "ADC(Pin(27))", "adc"),
        ("26", "ADC(0) (GP26)", "adc"),
        ("uart1", "UART(1)", "uart"),
        ("4", "Pin(4)", "pin"),
        ("5", "UART(rx=5)", "pin"),
    }
    assert "0" in pins({"main": "from machine import ADC\nADC(0)\n"}, family="esp32")  # not an RP2040: the id


@pytest.mark.parametrize(
    "source",
    [
        "ENC_PINS = (2, 3)\nencs = [Pin(p, Pin.IN) for p in ENC_PINS]\n",
        "ENC_PINS = [2, 3]\nencs = []\nfor p in ENC_PINS:\n    encs.append(Pin(p, Pin.IN))\n",
        "ENC_PINS = (2, 3)\na = Pin(ENC_PINS[0])\nb = Pin(ENC_PINS[1])\n",
    ],
)
def test_pins_in_tuples_and_lists(source):
    assert pins({"main": "from machine import Pin\n" + source}) == {"2": "ENC_PINS[0]", "3": "ENC_PINS[1]"}


MOTOR = """\
from machine import Pin, PWM
class Motor:
    def __init__(self, in1, in2, pwm, freq=1000):
        self.in1 = Pin(in1, Pin.OUT)
        self.in2 = Pin(in2, Pin.OUT)
        self._pwm_pin = pwm
        self.pwm = PWM(Pin(self._pwm_pin), freq=freq)
"""


@pytest.mark.parametrize(
    ("main", "expected"),
    [
        ("left = Motor(16, 17, 18)", {"16": "left.in1", "17": "left.in2", "18": "left.pwm"}),
        ("left = Motor(pwm=18, in2=17, in1=16, freq=20_000)", {"16": "left.in1", "17": "left.in2", "18": "left.pwm"}),
        ("AIN1, AIN2, PWMA = 16, 17, 18\nm = Motor(AIN1, AIN2, PWMA)", {"16": "AIN1", "17": "AIN2", "18": "PWMA"}),
        (  # a driver of drivers
            "class Robot:\n    def __init__(self, l1, l2, lp):\n        self.left = Motor(l1, l2, lp)\n"
            "bot = Robot(16, 17, 18)",
            {"16": "bot.l1", "17": "bot.l2", "18": "bot.lp"},
        ),
    ],
)
def test_drivers_called_with_ints_positional_or_by_keyword(main, expected):
    assert pins({"motor": MOTOR, "main": "from motor import Motor\n" + main + "\n"}) == expected


def test_public_drivers_as_they_are_written():
    hcsr04 = (  # rsc1975/micropython-hcsr04
        "import machine, time\nfrom machine import Pin\n"
        "class HCSR04:\n"
        "    def __init__(self, trigger_pin, echo_pin, echo_timeout_us=500*2*30):\n"
        "        self.echo_timeout_us = echo_timeout_us\n"
        "        self.trigger = Pin(trigger_pin, mode=Pin.OUT, pull=None)\n"
        "        self.trigger.value(0)\n"
        "        self.echo = Pin(echo_pin, mode=Pin.IN, pull=None)\n"
    )
    leds = "from machine import Pin\ndef make_leds(pins):\n    return [Pin(p, Pin.OUT) for p in pins]\n"
    main = (
        "from hcsr04 import HCSR04\nfrom leds import make_leds\n"
        "sensor = HCSR04(trigger_pin=5, echo_pin=18, echo_timeout_us=10000)\n"
        "LEDS = (12, 13)\nmake_leds(LEDS)\nmake_leds([25])\n"
    )
    found = pins({"hcsr04": hcsr04, "leds": leds, "main": main})
    assert found == {
        "5": "sensor.trigger_pin",
        "18": "sensor.echo_pin",
        "12": "LEDS[0]",
        "13": "LEDS[1]",
        "25": "pins[0]",
    }


def test_a_pin_computed_at_run_time_is_not_checked_and_not_guessed():
    result = scan({"main": "from machine import Pin\nimport json\ncfg = json.load(open('c.json'))\nPin(cfg['echo'])\n"})
    assert result.uses == [] and result.unchecked == ["main.py:4: Pin(cfg['echo'])"]


def test_check_reads_only_the_modules_the_entry_imports(tmp_path):
    (tmp_path / "main.py").write_text("import drv\nfrom machine import Pin\nPin(2)\n")
    (tmp_path / "drv.py").write_text("from machine import Pin\nPin(3)\n")
    (tmp_path / "old_test_rig.py").write_text("from machine import Pin\nPin(99)\n")
    assert {u.key for u in scan_folder(tmp_path, entry="main.py").uses} == {"2", "3"}
    assert {u.key for u in scan_folder(tmp_path).uses} == {"2", "3", "99"}  # (init reads every file)


# -- mpy-fil check -------------------------------------------------------------------------


BOT = """\
from machine import Pin
TRIG = 17
ECHO = 18
trig = Pin(TRIG, Pin.OUT)
led = Pin(25, Pin.OUT)


echo = Pin(ECHO, Pin.IN)
"""
RIG = """\
[board.pins]
TRIG = 17
ECHO = {echo}
LED = 25
[plant]
body = "bench"
[[plant.parts]]
kind = "probe"
name = "led"
[wiring]
TRIG = "probe:trig"
ECHO = "probe:echo"
LED = "led.in"
"""


def test_check_warns_naming_both_sides_when_the_rig_wires_another_pin(tmp_path, capsys):
    (tmp_path / "main.py").write_text(BOT)
    (tmp_path / "rig.toml").write_text(RIG.format(echo=16))
    assert cli.main(["check", str(tmp_path / "rig.toml")]) == 0
    err = capsys.readouterr().err.splitlines()
    assert err == [
        "check: the code uses Pin(18) (main.py:8, as ECHO) but the rig wires no pin 18; "
        "the rig wires ECHO = 16 (probe:echo), which the code never touches"
    ]
    assert cli.main(["check", "--strict", str(tmp_path / "rig.toml")]) == 1
    capsys.readouterr()
    (tmp_path / "rig.toml").write_text(RIG.format(echo=18))
    assert cli.main(["check", "--strict", str(tmp_path / "rig.toml")]) == 0
    assert capsys.readouterr().err == ""


def test_check_warns_for_each_side_alone(tmp_path, capsys):
    (tmp_path / "main.py").write_text(BOT.replace("led = Pin(25, Pin.OUT)", "") + "Pin(5)\nx = Pin(int(input()))\n")
    (tmp_path / "rig.toml").write_text(RIG.format(echo=18))
    assert cli.main(["check", "-v", str(tmp_path / "rig.toml")]) == 0
    out, err = capsys.readouterr()
    assert err.splitlines() == [
        "check: the code uses Pin(5) (main.py:9) but the rig wires no pin 5",
        "check: the rig wires LED = 25 (led.in), but the code never touches pin 25 "
        "(some pins are computed at run time: check -v lists them)",
    ]
    assert "not checked (computed at run time): main.py:10: Pin(int(input()))" in out


RIGS = sorted([*REPO.glob("firmware/apps/*/rig*.toml"), *REPO.glob("examples/*/rig.toml")])


@pytest.mark.parametrize("rig", RIGS, ids=[str(r.relative_to(REPO)) for r in RIGS])
def test_check_is_silent_for_every_rig_file_we_ship(rig):
    results = [check_pins(app) for app in apps_of(rig)]  # (each board of a rig with several)
    assert all(r.warnings == [] for r in results) and sum(r.checked for r in results) >= 7, results


# -- mpy-fil init --------------------------------------------------------------------------

TB6612 = """\
from machine import Pin, PWM
PWMA = PWM(Pin(16))
AIN1 = Pin(17, Pin.OUT)
AIN2 = Pin(18, Pin.OUT)
PWMB = PWM(Pin(21))
BIN1 = Pin(20, Pin.OUT)
BIN2 = Pin(19, Pin.OUT)
STBY = Pin(22, Pin.OUT)
trig = Pin(14, Pin.OUT)
"""
L298N = """\
from machine import Pin, PWM
ENA, IN1, IN2, ENB, IN3, IN4 = 14, 27, 26, 32, 25, 33
ena = PWM(Pin(ENA), freq=1000)
in1 = Pin(IN1, Pin.OUT)
in2 = Pin(IN2, Pin.OUT)
enb = PWM(Pin(ENB), freq=1000)
in3 = Pin(IN3, Pin.OUT)
in4 = Pin(IN4, Pin.OUT)
"""
DRV8833 = """\
from machine import Pin, PWM
class Motor:
    def __init__(self, in1, in2):
        self.a = PWM(Pin(in1), freq=20000)
        self.b = PWM(Pin(in2), freq=20000)
left = Motor(6, 7)
right = Motor(8, 9)
"""
DIR_PWM = """\
from machine import Pin, PWM
LEFT_DIR, LEFT_PWM, RIGHT_DIR, RIGHT_PWM = 4, 5, 6, 7
Pin(LEFT_DIR, Pin.OUT); PWM(Pin(LEFT_PWM)); Pin(RIGHT_DIR, Pin.OUT); PWM(Pin(RIGHT_PWM))
"""


@pytest.mark.parametrize(
    ("source", "bridge", "expected"),
    [
        (
            TB6612,
            "tb6612",
            {
                "PWMA = 16": 'PWMA = "motor_l.pwm"',
                "AIN1 = 17": 'AIN1 = "motor_l.in1"',
                "AIN2 = 18": 'AIN2 = "motor_l.in2"',
                "PWMB = 21": 'PWMB = "motor_r.pwm"',
                "BIN1 = 20": 'BIN1 = "motor_r.in1"',
                "BIN2 = 19": 'BIN2 = "motor_r.in2"',
                "STBY = 22": 'STBY = "probe:stby"',
                "TRIG = 14": '# TRIG = "..."',
            },
        ),
        (
            L298N,
            "l298n",
            {
                "ENA = 14": 'ENA = "motor_l.pwm"',
                "IN1 = 27": 'IN1 = "motor_l.in1"',
                "IN2 = 26": 'IN2 = "motor_l.in2"',
                "ENB = 32": 'ENB = "motor_r.pwm"',
                "IN3 = 25": 'IN3 = "motor_r.in1"',
                "IN4 = 33": 'IN4 = "motor_r.in2"',
            },
        ),
        (
            DRV8833,
            "drv8833",
            {
                "LEFT_IN1 = 6": 'LEFT_IN1 = "motor_l.in1"',
                "LEFT_IN2 = 7": 'LEFT_IN2 = "motor_l.in2"',
                "RIGHT_IN1 = 8": 'RIGHT_IN1 = "motor_r.in1"',
            },
        ),
        (
            DIR_PWM,
            "dir_pwm",
            {"LEFT_DIR = 4": 'LEFT_DIR = "motor_l.dir"', "RIGHT_PWM = 7": 'RIGHT_PWM = "motor_r.pwm"'},
        ),
    ],
    ids=["tb6612", "l298n", "drv8833", "dir_pwm"],
)
def test_init_names_the_pins_after_the_code_and_guesses_the_bridge(tmp_path, source, bridge, expected):
    (tmp_path / "main.py").write_text(source)
    text = starter(tmp_path)
    assert 'body = "differential"' in text and text.count(f'bridge = "{bridge}"') == 2, text
    for pin, wire in expected.items():
        assert f"\n{pin}\n" in text and f"\n{wire}\n" in text, (pin, wire, text)
    (tmp_path / "rig.toml").write_text(text)
    app = load_rig(tmp_path / "rig.toml")  # a rig file that loads as written
    assert {signal for signal in app.wiring.values()} >= {"motor_l.pwm", "motor_r.pwm"} or bridge == "drv8833"
    assert [w for w in check_pins(app).warnings if "never touches" in w] == []


def test_init_starts_from_a_usual_robots_parts_when_it_sees_no_bridge(tmp_path):
    (tmp_path / "main.py").write_text("from machine import Pin\nLED = Pin(25, Pin.OUT)\nbutton = Pin(13, Pin.IN)\n")
    text = starter(tmp_path)
    assert (
        'body = "differential"' in text
        and 'kind = "two_wheel"' not in text
        and "motor_l.pwm" not in text.split("[wiring]")[1]
    )
    assert "\nBUTTON = 13\n" in text and "\nLED = 25\n" in text


def test_init_on_our_examples_names_their_pins_as_their_rig_files_do(tmp_path):
    shutil.copy(REPO / "examples" / "two_sonar_bot" / "main.py", tmp_path / "main.py")
    text = starter(tmp_path)
    ours = load_rig(REPO / "examples" / "two_sonar_bot" / "rig.toml").board.pins
    written = dict(
        line.split(" = ")
        for line in text.split("[board.pins]")[1].split("[plant]")[0].splitlines()[1:]
        if " = " in line
    )
    assert {name: int(v) for name, v in written.items()} == ours
    assert text.count('bridge = "tb6612"') == 2
    assert 'name = "sonar_f"' in text and 'name = "sonar_r"' in text and '\nECHO_R = "sonar_r.echo"\n' in text
    (tmp_path / "rig.toml").write_text(text)
    assert check_pins(load_rig(tmp_path / "rig.toml")).checked == len(ours)


def test_an_rp2040_adc_channel_reads_the_gpio_check_says_it_is(make_rig, tmp_path):
    """``ADC(0)`` on a Pico is GP26: check compares it as pin 26, and a run wires it there too."""
    (tmp_path / "main.py").write_text(
        "import time\nfrom machine import ADC\nbat = ADC(0)\nwhile True:\n"
        "    print('BAT', bat.read_u16())\n    time.sleep_ms(100)\n"
    )
    (tmp_path / "rig.toml").write_text(
        '[board]\nfamily = "rpi_pico"\n[board.pins]\nBAT = 26\n[plant]\nbody = "bench"\n'
        '[[plant.parts]]\nkind = "battery"\nname = "battery"\n[wiring]\nBAT = "battery.adc"\n'
    )
    assert check_pins(load_rig(tmp_path / "rig.toml")).warnings == []
    rig = make_rig(str(tmp_path / "rig.toml"))
    reading = int(rig.expect(r"BAT (\d+)", timeout_s=1).group(1))
    assert abs(reading - 8.4 / 3 / 3.3 * 65535) < 65536 / 4096, "a full 2S battery through a 1:3 divider, 12 bits"


def test_a_file_that_cannot_be_read_is_said_not_silently_skipped(tmp_path, capsys):
    (tmp_path / "main.py").write_text("import drv\nfrom machine import Pin\nPin(2)\n")
    (tmp_path / "drv.py").write_text("from machine import Pin\nprint 'python 2'\nPin(3)\n")
    (tmp_path / "rig.toml").write_text(
        '[board.pins]\nA = 2\nB = 3\n[plant]\nbody = "bench"\n[wiring]\nA = "probe:a"\nB = "probe:b"\n'
    )
    assert cli.main(["check", str(tmp_path / "rig.toml")]) == 0
    out, err = capsys.readouterr()
    assert f"could not read {tmp_path / 'drv.py'} (line 2: Missing parentheses" in out
    assert err == (
        "check: the rig wires B = 3 (probe:b), but the code never touches pin 3 "
        "(some files could not be read: check lists them)\n"
    )


# -- buses: the devices' buses against those the code creates ----------------------------


@pytest.mark.parametrize(
    "source, made",
    [
        ("from machine import I2C, Pin\ni2c = I2C(1, sda=Pin(2), scl=Pin(3))\n", {"i2c1"}),
        ("from machine import I2C\ni2c = I2C(scl=22, sda=21)\n", {"i2c0"}),
        ("import machine\nspi = machine.SPI(2, baudrate=1_000_000)\n", {"spi2"}),
        ("from machine import SoftI2C, Pin\nb = SoftI2C(Pin(5), Pin(4))\n", {"i2c:5,4"}),
        ("from machine import SoftSPI\nb = SoftSPI(sck=14, mosi=13, miso=12)\n", {"spi:14,13,12"}),
    ],
)
def test_the_scanner_names_the_buses_the_code_creates_as_the_shim_names_them(source, made):
    assert set(scan({"main": source}).buses) == made


def test_check_names_a_device_on_a_bus_the_code_never_creates():
    from host.rig.scan.pincheck import compare_buses

    code = scan({"main": "from machine import I2C\ni2c = I2C(1)\n"})
    warnings = compare_buses(code, {"i2c0": ["imu"], "i2c1": ["baro"]})
    assert warnings == [
        "check: the rig puts imu on bus i2c0, but the code never creates i2c0 (the buses it creates: i2c1); "
        "I2C(n) is i2cn, SPI(n) spin, SoftI2C(scl, sda) i2c:<scl>,<sda>"
    ]
    computed = scan({"main": "from machine import I2C\nimport cfg\ni2c = I2C(cfg.BUS)\n"})
    assert compare_buses(computed, {"i2c0": ["imu"]}) == [], "a bus only a run can tell: no guess"


@pytest.mark.parametrize(
    "make",
    [
        "I2C(0, scl=Pin(5), sda=Pin(4), freq=400000)",
        "I2C(0, scl=5, sda=4)",
        "SoftI2C(Pin(5), Pin(4))",
        "SoftI2C(scl=Pin(5, Pin.OPEN_DRAIN), sda=Pin(4))",
        "SPI(1, sck=Pin(5), mosi=Pin(4), miso=Pin(19))",
    ],
)
def test_a_buss_lines_are_no_plant_signals_and_clash_with_a_wired_one(make):
    """Bus lines need no wiring (the rig puts chips on the bus by its name); a bus line on a
    pin the rig wires to a plant signal is a mistake on one side, named with both."""
    from host.rig.scan.pincheck import compare

    code = scan({"main": f"from machine import Pin, I2C, SoftI2C, SPI\nbus = {make}\nled = Pin(2, Pin.OUT)\n"})
    lines = {use.key for use in code.uses if use.kind == "bus"}
    assert {"5", "4"} <= lines and "2" not in lines, code.uses
    alone = compare(code, {"LED": 2}, {"LED": "led.in"})
    assert alone.warnings == [], f"expected no warning for bus lines the rig does not wire: {alone.warnings}"
    clash = compare(code, {"LED": 2, "ENC": 4}, {"LED": "led.in", "ENC": "enc.a"})
    assert len(clash.warnings) == 1 and "a bus line, on pin 4" in clash.warnings[0], clash.warnings
    assert "ENC = 4 to the plant's enc.a" in clash.warnings[0], clash.warnings


def test_an_spi_clock_line_wired_to_a_chips_clock_input_is_no_clash():
    """An SPI's sck= pin wired to a chip's ``<name>.sck`` (the pin of its clock, as parts that
    share MOSI have: docs/wiring.md) is right; its other lines there, and sck= on a signal of
    another kind, still clash."""
    from host.rig.scan.pincheck import compare

    code = scan({"main": "from machine import Pin, SPI\nbus = SPI(0, sck=Pin(6), mosi=Pin(3), miso=Pin(0))\n"})
    right = compare(code, {"LED_SCK": 6}, {"LED_SCK": "leds.sck"})
    assert right.warnings == [], f"expected no warning for the clock pin wired to leds.sck: {right.warnings}"
    wrong = compare(code, {"LED_SCK": 6, "DC": 0, "ENC": 3}, {"LED_SCK": "enc.a", "DC": "oled.sck", "ENC": "x.sck"})
    assert len(wrong.warnings) == 3, wrong.warnings
    assert all("a bus line, on pin" in w for w in wrong.warnings), wrong.warnings


@pytest.mark.parametrize("base", ["Pin(6)", "6", "Pin(6, Pin.IN, Pin.PULL_UP)"])
def test_the_pins_after_a_pio_groups_first_pin_are_a_note_not_a_warning(base):
    """A PIO program reads or drives as many pins from ``in_base`` (``out_base``, ``set_base``,
    ``sideset_base``) as it says; the scan cannot tell how many, so a wired pin after the first
    one the code names is a note; a wired pin before it, or far past it, still a warning."""
    from host.rig.scan.pincheck import compare

    source = f"import rp2\nfrom machine import Pin\nsm = rp2.StateMachine(0, prog, freq=1_000_000, in_base={base})\n"
    code = scan({"main": source}, family="rp2")
    assert any(use.kind == "pio" and use.key == "6" for use in code.uses), code.uses
    pins = {"ENC_A": 6, "ENC_B": 7, "LED": 5, "FAR": 40}
    wiring = {"ENC_A": "enc.a", "ENC_B": "enc.b", "LED": "led.in", "FAR": "probe.in"}
    result = compare(code, pins, wiring)
    assert [n for n in result.notes if "ENC_B = 7" in n and "in_base=6" in n], result
    assert not [w for w in result.warnings if "ENC_B" in w or "ENC_A" in w], result.warnings
    assert [w for w in result.warnings if "LED = 5" in w] and [w for w in result.warnings if "FAR = 40" in w], result


KIT = {  # a kit's library as kit vendors lay one out: a package in lib/, relative imports
    "lib/kit/__init__.py": "",
    "lib/kit/robot.py": "from .led import LED\nfrom .motors import Motors\nfrom .display import Display\n",
    "lib/kit/led.py": (
        "from machine import Pin\n\nclass LED:\n    def __init__(self):\n        self.pin = Pin(25, Pin.OUT)\n"
    ),
    "lib/kit/motors.py": (
        "from machine import Pin, PWM\nfrom ._lib.pins import LEFT_PWM, RIGHT_PWM\n\n"
        "class Motors:\n    def __init__(self):\n        self.left = PWM(Pin(LEFT_PWM))\n"
        "        self.right = PWM(Pin(RIGHT_PWM))\n"
    ),
    "lib/kit/_lib/__init__.py": "",
    "lib/kit/_lib/pins.py": "LEFT_PWM = const(15)\nRIGHT_PWM = const(14)\n",
    "lib/kit/_lib/screen.py": (
        "from machine import Pin\n\nclass Screen:\n    def __init__(self, dc):\n        self.dc = Pin(dc)\n"
    ),
    "lib/kit/display.py": (
        "from machine import Pin\nfrom ._lib import screen\n\nclass Display:\n    def __init__(self):\n"
        "        self.screen = screen.Screen(0)\n        self.res = Pin(1)\n"
    ),
    "sensors/__init__.py": "from .bump import BUMP\n",
    "sensors/bump.py": "from machine import Pin\nBUMP = Pin(16, Pin.IN)\n",
    "main.py": "from kit import robot\nimport sensors\nled, motors, d = robot.LED(), robot.Motors(), robot.Display()\n",
}


def test_check_counts_the_pins_used_in_lib_packages_and_package_folders_through_relative_imports(tmp_path, capsys):
    for name, text in KIT.items():
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text(text)
    scanned = scan_folder(tmp_path, [tmp_path / "lib"], entry="main.py", family="rp2")
    assert {u.key for u in scanned.uses} == {"25", "15", "14", "0", "1", "16"}, scanned
    wires = {"LED": 25, "ML": 15, "MR": 14, "DC": 0, "RES": 1, "BUMP": 16}
    pins_toml = "".join(f"{k} = {v}\n" for k, v in wires.items())
    parts = "".join(f'[[plant.parts]]\nkind = "probe"\nname = "{k.lower()}"\n' for k in wires)
    wiring = "".join(f'{k} = "{k.lower()}.in"\n' for k in wires)
    rig = f'[board]\nfamily = "rpi_pico"\n[board.pins]\n{pins_toml}[plant]\nbody = "bench"\n{parts}[wiring]\n{wiring}'
    (tmp_path / "rig.toml").write_text(rig)
    assert cli.main(["check", "--strict", str(tmp_path / "rig.toml")]) == 0, capsys.readouterr().err
    assert "never touches" not in capsys.readouterr().err


def test_init_sets_the_rp2_family_when_the_code_names_rp2(tmp_path):
    """SunFounder's Pico-4WD library (``from rp2 import PIO, StateMachine, asm_pio``) runs on a
    Pico: the rig file init writes says so, where it left [board] out and the first run
    stopped at ``ImportError: no module named 'rp2'``."""
    (tmp_path / "main.py").write_text(
        "from machine import Pin, PWM\nfrom rp2 import PIO, StateMachine, asm_pio\nservo = PWM(Pin(18, Pin.OUT))\n"
    )
    text = starter(tmp_path)
    assert '\n[board]\nfamily = "rpi_pico"' in text, text
    (tmp_path / "rig.toml").write_text(text)
    assert load_rig(tmp_path / "rig.toml").board.identity[0] == "rp2", text
    (tmp_path / "main.py").write_text("from machine import Pin\nLED = Pin(2, Pin.OUT)\n")
    assert "[board]" not in starter(tmp_path), "no family for code that names none"
