"""Pins and the board as each family's port has them (docs/shim.md, "Pins"): the Pin
constants, Pin.ALT and alt=, Pin.board/Pin.cpu and string names, machine.freq(), and
rp2.bootsel_button() pressed by the rig file."""

from pathlib import Path

import pytest

from host.cli import main
from host.rig.config.app import App
from host.rig.hardware.wiring import Wiring
from host.tests.conftest import FIRMWARE, bench_app, results

pytestmark = pytest.mark.hil

SCENARIOS = Path(__file__).parent / "wokwi_scenarios"
RP2040 = ("rp2", "Raspberry Pi Pico with RP2040")
RP2350 = ("rp2", "Raspberry Pi Pico2 with RP2350")
ESP32 = ("esp32", "Generic ESP32 module with ESP32")

# ports/rp2/machine_pin.h (MACHINE_PIN_MODE_*), ports/rp2/machine_pin.c (GPIO_PULL_UP 1,
# GPIO_PULL_DOWN 2, GPIO_IRQ_EDGE_RISE 8, GPIO_IRQ_EDGE_FALL 4, the ALT_* as pico-sdk's
# GPIO_FUNC_*); no ALT_OPEN_DRAIN on rp2
RP2_COMMON = {"IN": 0, "OUT": 1, "OPEN_DRAIN": 2, "ALT": 3, "PULL_UP": 1, "PULL_DOWN": 2}
RP2_COMMON |= {"IRQ_RISING": 8, "IRQ_FALLING": 4, "ALT_SPI": 1, "ALT_UART": 2, "ALT_I2C": 3, "ALT_PWM": 4}
RP2_COMMON |= {"ALT_SIO": 5, "ALT_PIO0": 6, "ALT_PIO1": 7}
# ports/esp32/machine_pin.c: GPIO_MODE_INPUT 1, GPIO_MODE_INPUT_OUTPUT 3, _OD 7, its own
# GPIO_PULL_DOWN 1 / GPIO_PULL_UP 2, GPIO_INTR_POSEDGE 1 / NEGEDGE 2; no ALT at all
ESP32_CONSTS = {"IN": 1, "OUT": 3, "OPEN_DRAIN": 7, "PULL_UP": 2, "PULL_DOWN": 1, "IRQ_RISING": 1, "IRQ_FALLING": 2}

RP2_NAMES = {  # ports/rp2/machine_pin.c, machine_pin_find; boards/RPI_PICO/pins.csv
    "led": "True",
    "gp14": "True",
    "gpio29": "True",
    "unknown": 'ValueError: unknown named pin "NOPE"',
    "board_gp23": "AttributeError: type object 'board' has no attribute 'GP23'",  # (the SMPS pin: not in pins.csv)
    "alt_kw": "Pin(GPIO6, mode=OUT)",  # (alt= with a mode of SIO's: no function chosen; machine_pin_print)
    "bad_af": "ValueError: invalid pin af: 8",  # (GPCK is GP20..GP25's alone, boards/rp2_af.csv)
    "irq_hard": "'ok'",  # machine_pin_irq: handler, trigger, hard
    "irq_hard_pos": "'ok'",
    "irq_wake": "TypeError: extra keyword arguments given",  # (py/argcheck.c, mp_arg_parse_all)
}
ESP32_NAMES = {  # ports/esp32/machine_pin.c: a generic board's Pin.board is empty; init has no alt=
    "led": "ValueError: invalid pin",
    "gp14": "ValueError: invalid pin",
    "gpio29": "AttributeError: type object 'Pin' has no attribute 'cpu'",
    "unknown": "ValueError: invalid pin",
    "board_gp23": "AttributeError: type object 'board' has no attribute 'GP23'",
    "alt_kw": "TypeError: extra keyword arguments given",  # (machine_pin_obj_init_helper: mp_arg_parse_all)
    "bad_af": "AttributeError: type object 'Pin' has no attribute 'ALT'",
    # machine_pin_irq: handler, trigger, wake (no hard: a pin's handler is always scheduled)
    "irq_hard": "TypeError: extra keyword arguments given",
    "irq_hard_pos": "'ok'",  # (the third positional is wake: None, no wake)
    "irq_wake": "'ok'",
}
CANNOT = "ValueError: cannot change frequency"  # ports/rp2/modmachine.c: set_sys_clock_khz failed
ESP32_ONLY = "ValueError: frequency must be 20MHz, 40MHz, 80Mhz, 160MHz or 240MHz"  # ports/esp32/modmachine.c
CASES = {
    # (pico-sdk: a 12 MHz crystal, the VCO at 750..1600 MHz, two post dividers of 1..7)
    "rp2040": (
        RP2040,
        RP2_COMMON | {"ALT_GPCK": 8, "ALT_USB": 9},
        True,
        RP2_NAMES,
        125_000_000,
        {133: ("None", 133), 200: ("None", 200), 240: ("None", 240), 80: ("None", 80), 123: (CANNOT, 80)},
    ),
    "rp2350": (
        RP2350,
        RP2_COMMON | {"ALT_GPCK": 9, "ALT_USB": 10},
        True,
        RP2_NAMES,  # (8 is PIO2 on an RP2350, but 1.25's boards/rp2_af.csv gives no GPIO PIO2)
        150_000_000,
        {133: ("None", 133), 200: ("None", 200), 240: ("None", 240), 80: ("None", 80), 123: (CANNOT, 80)},
    ),
    "esp32": (
        ESP32,
        ESP32_CONSTS,
        False,
        ESP32_NAMES,
        160_000_000,  # ESP-IDF's default for a generic ESP32 (boards/sdkconfig.base keeps it)
        {133: (ESP32_ONLY, 160), 200: (ESP32_ONLY, 160), 240: ("None", 240), 80: ("None", 80), 123: (ESP32_ONLY, 80)},
    ),
}
SET_HZ = {133: 133_000_000, 200: 200_000_000, 240: 240_000_000, 80: 80_000_000, 123: 123_456_789}


def run(make_rig, case: str, identity, app=None, duration_s: float = 1.0):
    app = app or bench_app(case, {"body": "bench"}, board="pins", identity=identity)
    rig = make_rig(app, main_dir=FIRMWARE / case, allow_exit=True)
    rig.run_for(duration_s)
    rig.stop()
    return rig, results(rig.console)


@pytest.mark.parametrize("family", sorted(CASES))
def test_pin_constants_names_and_freq_are_the_ports_own_per_family(make_rig, family):
    identity, consts, has_cpu, names, freq, sets = CASES[family]
    rig, r = run(make_rig, "pin_family", identity)
    assert r["consts"] == consts, rig.console
    assert r["has_cpu"] is has_cpu
    for key, expected in names.items():
        assert r[key] == expected, (key, rig.console)
    assert r["freq"] == freq
    peri = {  # rp2: a peripheral clock of 48 MHz or the CPU's; esp32's freq() takes one argument
        "rp2": "ValueError: peripheral freq must be 48_000_000 or the same as the MCU freq",
        "esp32": "TypeError: function expected at most 1 arguments, got 2",
    }
    assert r["peri"] == peri[identity[0]]
    for mhz, (said, now_mhz) in sets.items():
        got = r[f"set_{SET_HZ[mhz]}"]
        assert got == (said, now_mhz * 1_000_000), (mhz, got)


SPI_BENCH = {"body": "bench", "parts": [{"kind": "lsm6dsox", "name": "imu", "bus": "spi1", "spi": True}]}
SPI_PINS = {"IMU_CS": 9, "OUT": 2, "SEEN": 3}
SPI_WIRING = {"IMU_CS": "imu.cs", "OUT": "w.in", "SEEN": "w.out"}


def test_a_pin_handed_back_to_spi_with_pin_alt_then_the_bus_reads_the_chip(make_rig):
    """ports/rp2/machine_pin.c: init(mode=Pin.ALT, alt=Pin.ALT_SPI) gives GP10 to SPI1
    (gpio_set_function); in ALT, value(x) sets SIO's latch only, which reaches the pad
    when the pin is OUT again."""
    plant = {**SPI_BENCH, "parts": SPI_BENCH["parts"] + [{"kind": "wire", "name": "w"}]}
    app = bench_app("pin_alt", plant, board="rpi_pico_bench", wiring=SPI_WIRING, pins=SPI_PINS)
    rig, r = run(make_rig, "pin_alt", RP2040, app)
    assert r["repr"] == "Pin(GPIO10, mode=ALT, alt=1)", rig.console
    assert r["who"] == [0x6C]
    assert r["levels"] == [1, 1, 0], "ALT: the pad keeps its level while value(0) waits in the latch"


BOOTSEL_PRESSES = [[0.5, 0.6], [1.0, 1.1], [1.5, 1.6]]


def bootsel_app(presses=BOOTSEL_PRESSES, wiring=None) -> App:
    plant = {"body": "bench", "parts": [{"kind": "button", "name": "boot", "presses": presses}]}
    return bench_app(
        "bootsel", plant, board="rpi_pico_bench", wiring={"BOOTSEL": "boot.out"} if wiring is None else wiring
    )


def test_a_menu_waiting_for_bootsel_goes_on_when_the_rig_files_button_presses_it(make_rig):
    rig, r = run(make_rig, "bootsel_menu", RP2040, bootsel_app(), duration_s=2.0)
    assert r["idle"] == 0, rig.console
    assert 500 <= r["started_ms"] <= 511
    assert 1000 <= r["item1_ms"] <= 1011 and 1500 <= r["item2_ms"] <= 1511


def test_an_unwired_bootsel_is_never_pressed(make_rig):
    rig, r = run(make_rig, "bootsel_menu", RP2040, bootsel_app(wiring={}), duration_s=1.0)
    assert r["idle"] == 0 and "started_ms" not in r, rig.console


@pytest.mark.parametrize("wired", [False, True])
def test_adc_channel_4_reads_the_temperature_sensor_at_27_c_or_what_the_rig_wires(make_rig, wired):
    """ports/rp2/machine_adc.c, mp_machine_adc_make_new: an int below NUM_ADC_CHANNELS is a
    channel, 4 the temperature sensor (ADC.CORE_TEMP), not GPIO 4 (it read 0 there: 437
    degrees C by the datasheet's formula). Unwired, 0.706 V (27 degrees C) as the 12-bit
    reading scales; a rig wires it by its name, CORE_TEMP."""
    parts = [{"kind": "potentiometer", "name": "knob", "position": 0.6}]
    wiring = {"KNOB": "knob.sig"}
    if wired:
        parts.append({"kind": "potentiometer", "name": "die", "position": 0.2})
        wiring["CORE_TEMP"] = "die.sig"
    app = bench_app(
        "core_temp", {"body": "bench", "parts": parts}, board="rpi_pico_bench", wiring=wiring, pins={"KNOB": 26}
    )
    rig, r = run(make_rig, "core_temp", RP2040, app)
    temp_u16 = rig.plant.output("die.sig") if wired else 876 << 4 | 876 >> 8  # (round(0.706 / 3.3 * 4095))
    assert r["channel"] == 4 and r["temp_u16"] == (temp_u16, temp_u16), f"expected {temp_u16}: {r} {rig.console}"
    knob_u16 = rig.plant.output("knob.sig")
    assert r["gp26_u16"] == (knob_u16, knob_u16), f"expected the knob's {knob_u16} on GP26: {r} {rig.console}"


def test_a_rigs_gp_name_is_wired_to_the_pin_the_shim_names_by_number():
    """Pin("GP14") is Pin(14) on an rp2 (the shim sends 14): a rig's "GP14" or "GPIO14" is that pin."""
    wiring = Wiring({"A": "a.out", "B": "b.out"}, {"A": "GP14", "B": "GPIO15"}, "pins")
    assert wiring.signal_of("14") == "a.out" and wiring.signal_of("15") == "b.out"


def test_check_takes_the_bootsel_line_and_pin_led_as_the_pins_the_rig_wires(capsys):
    """The scenario's rig wires BOOTSEL (read by rp2.bootsel_button(), which check cannot
    see) and LED = 25, which the code makes as Pin("LED"): no warning for either."""
    assert main(["check", str(SCENARIOS / "bootsel_menu" / "rig.toml")]) == 0
    out = capsys.readouterr().out
    assert "pins the code uses: 1 compared with the wiring" in out
    assert "never touches" not in out and "wires no pin" not in out, out
