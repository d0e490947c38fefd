"""Rig files: our apps are rig files, a folder of one's own runs from one, and every
mistake names the file and the field."""

import re
import subprocess
import sys
import textwrap

import pytest

from host.core.errors import ConfigError, FirmwareError
from host.core.paths import FIRMWARE, REPO
from host.rig.config.apps import apps, get_app
from host.rig.config.rigfile import load_rig

GOOD = """
name = "mybot"
[firmware]
entry = "main.py"
[board.pins]
LEFT_PWM = 25
LEFT_IN1 = 26
LEFT_IN2 = 27
BUMP = 23
LED = 2
[plant]
body = "differential"
room_w_m = 4.0
[[plant.parts]]
kind = "dc_motor"
name = "motor_l"
drives = "left"
[[plant.parts]]
kind = "dc_motor"
name = "motor_r"
drives = "right"
[[plant.parts]]
kind = "bumper"
name = "bumper"
[wiring]
LEFT_PWM = "motor_l.pwm"
LEFT_IN1 = "motor_l.in1"
LEFT_IN2 = "motor_l.in2"
BUMP = "bumper.out"
LED = "probe:led"
[budgets.blink]
kind = "period"
source = "probe:led"
period_us = 100_000
tolerance_us = 0
description = "the LED toggles every {period_ms:g} ms"
[worlds.small]
room_w_m = 2.0
"""

BLINK = """
from machine import Pin
import time

led = Pin(2, Pin.OUT)
bump = Pin(23, Pin.IN, Pin.PULL_UP)
for _ in range(20):
    led.toggle()
    time.sleep_ms(100)
print("blinked; bumper", bump.value())
"""


def write_rig(folder, text=GOOD, files=None):
    folder.mkdir(parents=True, exist_ok=True)
    for name, source in (files or {"main.py": BLINK}).items():
        (folder / name).write_text(textwrap.dedent(source))
    path = folder / "rig.toml"
    path.write_text(textwrap.dedent(text))
    return path


def test_our_apps_are_rig_files():
    found = apps()
    assert set(found) == {
        "rover",
        "pool_cleaner",
        "pool_cleaner_adc",
        "lab_robot",
        "lab_robot_canyon",
        "vacuum",
        "duct",
    }
    rover = found["rover"]
    assert rover.rig_file == FIRMWARE / "apps" / "rover" / "rig.toml" and rover.code.harness_lib
    assert len(rover.wiring) == 13 and list(rover.worlds) == ["room", "long-room", "small-room"]
    plant = rover.make_plant(**rover.worlds["small-room"])
    assert plant.body.options["room_w_m"] == 3.0 and plant.body.options["start_pose"] == [1.0, 1.5, 0.0]
    names = [b.name for b in rover.make_budgets(plant)]
    assert names == ["control.period", "sonar.period", "sonar.latency", "control.compute"]
    adc = found["pool_cleaner_adc"]
    assert adc.path == found["pool_cleaner"].path and "sonar_l.adc" in adc.make_plant().outputs
    canyon = found["lab_robot_canyon"]
    assert canyon.path == found["lab_robot"].path and canyon.board.also == ("esp32_lab_robot", "rpi_pico_lab_robot")
    vacuum = found["vacuum"]
    assert list(vacuum.code.lib_dirs) == [vacuum.path / "lib"] and vacuum.board.also == (
        "esp32_vacuum",
        "rpi_pico_vacuum",
    )


def test_a_rig_file_of_ones_own_loads_with_its_pins_table(tmp_path):
    app = load_rig(write_rig(tmp_path / "mybot"))
    assert app.name == "mybot" and app.default_board == "pins" and app.board.pins["LED"] == 2
    assert not app.code.harness_lib and app.firmware_folders(None) == [tmp_path / "mybot"]
    budget = app.make_budgets(app.make_plant())[0]
    assert budget.period_us == 100_000 and budget.description == "the LED toggles every 100 ms"


def test_a_rig_file_runs_in_the_loop_by_its_path(make_rig, tmp_path):
    rig = make_rig(str(write_rig(tmp_path / "mybot")), seed=1, allow_exit=True)
    rig.run_for(3)
    rig.stop()
    assert f"blinked; bumper {rig.plant.output('bumper.out')}" in rig.console, rig.console
    assert rig.budgets["blink"].stats()["count"] == 19 and rig.budgets["blink"].misses == 0


def test_the_entry_file_may_have_another_name(make_rig, tmp_path):
    text = GOOD.replace('entry = "main.py"', 'entry = "robot.py"')
    rig = make_rig(str(write_rig(tmp_path / "mybot", text, {"robot.py": BLINK})), seed=1, allow_exit=True)
    rig.run_for(3)
    rig.stop()
    assert "blinked" in rig.console, rig.console


def test_our_firmware_library_is_not_on_a_users_path_unless_asked(make_rig, tmp_path):
    uses_ours = {"main.py": "import encoder\nprint('found', encoder.__name__)\n"}
    with pytest.raises(FirmwareError, match="no module named 'encoder'.*\n.*harness_lib = true"):
        make_rig(str(write_rig(tmp_path / "a", GOOD, uses_ours))).run_for(0.1)
    text = GOOD.replace('entry = "main.py"', 'entry = "main.py"\nharness_lib = true')
    rig = make_rig(str(write_rig(tmp_path / "b", text, uses_ours)), allow_exit=True)
    rig.run_for(0.1)
    rig.stop()
    assert "found encoder" in rig.console


@pytest.mark.parametrize(
    ("change", "field", "says"),
    [
        (('"motor_l.pwm"', '"motor_l.pwn"'), "[wiring] LEFT_PWM", "no signal 'motor_l.pwn' (inputs: motor_l.in1"),
        (('BUMP = "bumper.out"', 'BUMPR = "bumper.out"'), "[wiring] BUMPR", "has no pin named BUMPR (pins: LEFT_PWM"),
        (('entry = "main.py"', 'entyr = "main.py"'), "[firmware] entyr", "did you mean 'entry'?"),
        (('entry = "main.py"', 'entry = "robot.py"'), "[firmware] entry", "no robot.py in"),
        (('entry = "main.py"', "harness_lib = 1"), "[firmware] harness_lib", "expected true/false, got 1"),
        (("room_w_m = 4.0", "room_w_m = 0.2"), "[plant] start_pose", "puts the robot outside the room"),
        (("room_w_m = 4.0", "room_w_m = -1.0"), "[plant] room_w_m", "from 0.1 to 100, got -1.0"),
        (("room_w_m = 4.0", "room_w = 4.0"), "[plant] room_w", "options: world, world_options, room_w_m"),
        (
            ("room_w_m = 4.0", 'room_w_m = "4"'),
            "[plant] room_w_m",
            "expected a number of metres from 0.1 to 100, got '4'",
        ),
        (("room_w_m = 4.0", "start_pose = [1, '2', 0]"), "[plant] start_pose", "item 1: expected a number of metres"),
        (("LED = 2\n", "LED = 25\n"), "[wiring] LED", "pin 25 is LEFT_PWM too"),
        (("period_us = 100_000", "period_us = -100_000"), "[budgets.blink] period_us", "expected 1 to 3600000000"),
        (('source = "probe:led"', 'source = "probe:lde"'), "[budgets.blink] source", "no pin is wired to 'probe:lde'"),
        (('body = "differential"', 'body = "rover"'), "[plant] body", "expected one of"),
        (('source = "probe:led"', 'source = "led"'), "[budgets.blink] source", "no signal 'led'"),
        (("tolerance_us = 0", 'tolerance_us = "0"'), "[budgets.blink] tolerance_us", "expected an integer"),
        (("room_w_m = 2.0", "room_w_m = 0.1"), "[worlds.small]", "puts the robot outside the room"),
        (("room_w_m = 2.0", "rom_w_m = 2.0"), "[worlds.small]", "rom_w_m: the differential has no such option"),
        (("{period_ms:g}", "{period:g}"), "[budgets.blink] description", "cannot fill in 'period'"),
    ],
)
def test_every_mistake_names_the_file_and_the_field(tmp_path, change, field, says):
    path = write_rig(tmp_path / "mybot", GOOD.replace(*change))
    with pytest.raises(ConfigError) as e:
        load_rig(path)
    assert str(e.value).startswith(f"{path}: {field}: "), str(e.value)
    assert says in str(e.value), str(e.value)


def test_a_board_file_with_a_syntax_error_is_named_with_its_line(tmp_path):
    text = GOOD.split("[board.pins]")[0] + '[board]\nfile = "board.py"\n' + GOOD.split("LED = 2\n")[1]
    path = write_rig(tmp_path / "mybot", text, {"main.py": BLINK, "board.py": "A = const(1)\nB = = 2\n"})
    with pytest.raises(ConfigError, match=r"\[board\] file: .*board.py:2: SyntaxError"):
        load_rig(path)


def test_a_rig_file_that_is_not_toml_says_where(tmp_path):
    path = write_rig(tmp_path / "mybot", GOOD + "\n[wiring\n")
    with pytest.raises(ConfigError, match=r"rig.toml: not valid TOML: .*line"):
        load_rig(path)
    with pytest.raises(ConfigError, match="no such rig file"):
        get_app(str(tmp_path / "nothing" / "rig.toml"))


def mpy_fil(*args):
    return subprocess.run(
        [sys.executable, "-m", "host.cli", *args], cwd=REPO, capture_output=True, text=True, timeout=60
    )


def test_mpy_fil_check_lists_the_plants_signals_and_a_mistake_exits_2_in_one_line(tmp_path):
    path = write_rig(tmp_path / "mybot")
    done = mpy_fil("check", str(path))
    assert done.returncode == 0, done.stderr
    assert "inputs (the firmware drives): motor_l.in1 (level)" in done.stdout and "budget blink" in done.stdout
    path.write_text(GOOD.replace('"motor_l.pwm"', '"motor_l.pwn"'))
    done = mpy_fil("check", str(path))
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert f"{path}: [wiring] LEFT_PWM: the plant has no signal 'motor_l.pwn'" in done.stderr, done.stderr


def test_mpy_fil_init_writes_a_starting_rig_file_with_the_pins_the_code_uses(tmp_path):
    folder = tmp_path / "bot"
    folder.mkdir()
    (folder / "main.py").write_text(
        "from machine import Pin, PWM\nLED, BTN = 25, 13\n\nclass Motor:\n    def __init__(self, pwm, d):\n"
        "        self.pwm = PWM(Pin(pwm))\n        self.d = Pin(d, Pin.OUT)\n\nm = Motor(16, 17)\n"
        "left = Motor(LEFT_PWM, 18) if False else None\nLEFT_PWM = 21\nled = Pin(LED, Pin.OUT)\nb = Pin(BTN)\n"
    )
    (folder / "lib").mkdir()
    (folder / "lib" / "ranger.py").write_text(
        "from machine import Pin\n\nclass Ranger:\n    def __init__(self, trig, echo):\n        self.t = Pin(trig)\n"
        "        self.e = Pin(echo)\n"
    )
    (folder / "main.py").write_text((folder / "main.py").read_text() + "TRIG, ECHO = 14, 15\nr = Ranger(TRIG, ECHO)\n")
    done = mpy_fil("init", str(folder))
    assert done.returncode == 0, done.stderr
    text = (folder / "rig.toml").read_text()
    assert "LED = 25\n" in text and "BTN = 13\n" in text and "LEFT_PWM = 21\n" in text, text
    assert "M_PWM = 16\n" in text and "M_D = 17\n" in text, "numbers given to a driver: named as the code names them"
    assert "TRIG = 14\n" in text and "ECHO = 15\n" in text, "the pins given to a driver class in lib/"
    assert mpy_fil("check", str(folder / "rig.toml")).returncode == 0
    again = mpy_fil("init", str(folder))
    assert again.returncode == 2 and "exists" in again.stderr and "Traceback" not in again.stderr


def test_mpy_fil_list_shows_apps_boards_bodies_and_parts_with_their_signals():
    done = mpy_fil("list")
    assert done.returncode == 0, done.stderr
    for text in ("rover ", "rpi_pico", "differential", "trigger_min_us=2", "signals: <name>.trig, <name>.echo"):
        assert text in done.stdout, text
    assert "plant kinds" not in done.stdout, "one plant generation: no heading of kinds"


HEAP_AND_TICKS = """
import gc
import time

gc.collect()
print("heap", gc.mem_free())
t0 = time.ticks_ms()
time.sleep_ms(1500)
print("wrapped", time.ticks_ms() < t0)
"""


def test_interpreter_settings_give_the_heap_and_when_the_ticks_wrap(make_rig, tmp_path):
    text = GOOD + '\n[interpreter]\nheap_size = "128K"\nticks_wrap_s = 1\n'
    rig = make_rig(str(write_rig(tmp_path / "mybot", text, {"main.py": HEAP_AND_TICKS})), allow_exit=True)
    rig.run_for(2)
    rig.stop()
    heap = int(rig.console.split("heap ")[1].split()[0])
    # (the firmware's free heap is its board's: the shim's own is on top, host/rig/targets/firmware.py)
    assert 120 * 1024 < heap <= 136 * 1024 and "wrapped True" in rig.console, rig.console
    bad = write_rig(tmp_path / "other", GOOD + '\n[interpreter]\nheap_size = "lots"\n')
    with pytest.raises(ConfigError, match=r"\[interpreter\] heap_size: expected bytes from 24K to 1024M, like 192K"):
        load_rig(bad)


def test_a_period_budget_takes_the_plants_own_sample_period_by_default(tmp_path):
    text = GOOD.replace(
        "[wiring]", '[[plant.parts]]\nkind = "analog_ranger"\nname = "ranger"\nperiod_us = 40_000\n[wiring]'
    )
    text = text.replace("room_w_m = 2.0", "room_h_m = 1.5")
    text += '\n[budgets.ranger]\nkind = "period"\nsource = "ranger.adc"\ntolerance_us = 0\n'
    app = load_rig(write_rig(tmp_path / "mybot", text))
    budget = [b for b in app.make_budgets(app.make_plant()) if b.name == "ranger"][0]
    assert budget.period_us == 40_000
    bad = text.replace('source = "ranger.adc"', 'source = "bumper.out"')
    with pytest.raises(ConfigError, match=r"\[budgets.ranger\] period_us: missing, and the plant samples bumper.out"):
        load_rig(write_rig(tmp_path / "other", bad))


def test_make_flash_stages_a_rig_files_firmware_without_its_tests(tmp_path):
    from host.device import flash

    folder, files = flash.stage(str(REPO / "examples" / "pico_bot" / "rig.toml"), "pins", root=tmp_path)
    assert files == ["main.py"] and (folder / "main.py").is_file(), files


@pytest.mark.parametrize(
    ("code", "says"),
    [
        (
            "from machine import Pin\nPin(23, Pin.OUT).value(1)\n",
            "drives pin BUMP (23) as an output, but it is wired to bumper.out",
        ),
        (
            "from machine import ADC, Pin\nADC(Pin(23)).read_u16()\n",
            "reads pin BUMP (23) with an ADC, but bumper.out is a logic level",
        ),
    ],
)
def test_a_firmware_that_drives_a_sensor_line_or_reads_a_level_with_an_adc_is_stopped(make_rig, tmp_path, code, says):
    rig = make_rig(str(write_rig(tmp_path / "mybot", GOOD, {"main.py": code})))
    with pytest.raises(ConfigError, match=re.escape(says)):
        rig.run_for(0.1)


def test_a_users_test_that_makes_a_rig_is_selected_as_hil_unmarked(tmp_path):
    """`make hil RIG=…` runs `pytest -m hil` on the rig file's folder: a test of one's own
    that uses make_rig counts as hil without a mark."""
    rig = write_rig(tmp_path / "mybot")
    (tmp_path / "mybot" / "test_mybot.py").write_text(
        f"def test_blinks(make_rig):\n    make_rig({str(rig)!r}, seed=1).run_for(1)\n"
    )
    done = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-m", "hil", str(tmp_path / "mybot")],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0 and "1 passed" in done.stdout, done.stdout + done.stderr
