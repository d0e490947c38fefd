"""machine.mem32/mem16/mem8 on an RP2040 (docs/shim.md, "Registers"): the PWM slices'
registers drive the plant as machine.PWM does, IO_BANK0's function select and overrides
and SIO's GPIO registers drive and read the pins, and any other address is named once."""

import pytest

from host.rig.config.app import App, BoardSettings
from host.tests.conftest import FIRMWARE, INPUTS, OUTPUTS, bench_app, results
from sim_plant.scripted import ScriptedPlant

pytestmark = pytest.mark.hil

RP2040 = ("rp2", "Raspberry Pi Pico with RP2040")
ROBOT = {
    "body": "differential",
    "room_w_m": 3.0,
    "room_h_m": 2.0,
    "start_pose": [0.5, 1.0, 0.0],
    "parts": [
        {"kind": "dc_motor", "name": "motor_l", "bridge": "dir_pwm", "drives": "left", "time_constant_ms": 0},
        {"kind": "dc_motor", "name": "motor_r", "bridge": "dir_pwm", "drives": "right", "time_constant_ms": 0},
    ],
}
PINS = {"R_DIR": 10, "L_DIR": 11, "R_PWM": 14, "L_PWM": 15}
WIRING = {"R_DIR": "motor_r.dir", "L_DIR": "motor_l.dir", "R_PWM": "motor_r.pwm", "L_PWM": "motor_l.pwm"}


def drive(make_rig, case, identity=RP2040):
    app = bench_app(case, ROBOT, board="pins", identity=identity, wiring=WIRING, pins=PINS)
    rig = make_rig(app, main_dir=FIRMWARE / case, allow_exit=True)
    rig.run_for(0.5)
    half = rig.truth()
    rig.run_for(1.0)
    rig.stop()
    return rig, half, results(rig.console)


def test_motors_driven_through_pwm_registers_move_as_with_pwm_duty(make_rig):
    rig, half, r = drive(make_rig, "mem32_motors")
    _, twin_half, twin = drive(make_rig, "pwm_motors")
    assert half["distance_m"] > 0.1, (half, rig.console)  # it moved
    assert half["x_m"] == pytest.approx(twin_half["x_m"], abs=1e-9), (half, twin_half)
    assert half["theta_rad"] == pytest.approx(twin_half["theta_rad"], abs=1e-9)
    assert half["distance_m"] == pytest.approx(twin_half["distance_m"], abs=1e-9)
    # ports/rp2/machine_pwm.c: PWM(freq=20833) sets DIV 16, TOP 5999; duty_u16 from CC and TOP
    assert r["made"] == [5999, 16, 0, 1], rig.console
    assert r["regs"] == [5999, 16, hex(3000 << 16 | 4500), 4500, 3000]
    assert r["pwm"] == [32768, 49151, 20833, 20833] == twin["pwm"]
    assert r["unknown"] == [0, 0] and r["unknown_back"] == 0x1234
    assert r["stopped"] == [0, 0, 32768] and r["running"] == [1, 5999]  # (duty_u16(): from CC, running or not)
    assert r["from_pwm"] == [hex(3000), 5999]  # (duty_u16(32768) on TOP 5999: CC A = 3000)
    # freq(1000): TOP 124999 does not fit 16 bits, so div16 = ceil(16 * 125 MHz / (65534 * 1000))
    # = 31 and TOP = round(16 * 125 MHz / (31 * 1000)) - 1 (machine_pwm.c, mp_machine_pwm_freq_set)
    assert r["freq_regs"] == [64515, 31, 1000, 32768]
    notes = [line for line in rig.console.splitlines() if "0x40058000" in line]
    assert len(notes) == 1 and "[mpy-fil: note: read of 0x40058000" in notes[0], rig.console


def test_a_slice_set_up_through_registers_alone_drives_its_pins_once_funcsel_gives_them_to_pwm(make_rig):
    rig, half, _ = drive(make_rig, "mem32_bare_motors")
    _, twin_half, _ = drive(make_rig, "pwm_motors")
    assert half["distance_m"] > 0.1, (half, rig.console)
    assert half["x_m"] == pytest.approx(twin_half["x_m"], abs=1e-9), (half, twin_half)
    assert half["theta_rad"] == pytest.approx(twin_half["theta_rad"], abs=1e-9)
    assert "[mpy-fil: note" not in rig.console, rig.console


def gpio_app():
    # GP16 -> the plant's out1 (a level it takes), GP17 <- its button (pressed 40..90 ms)
    script = [(40_000, "button", 0), (90_000, "button", 1)]
    return App(
        name="mem32_gpio",
        default_board="pins",
        make_plant=lambda: ScriptedPlant(script, outputs=OUTPUTS, inputs=INPUTS, initial={"button": 1}),
        wiring={"OUT1": "out1", "BTN": "button"},
        board=BoardSettings(pins={"OUT1": 16, "BTN": 17}, identity=RP2040, console_baud=0),
    )


def test_sio_registers_drive_pins_and_an_override_reads_a_button_on_an_led_pin(make_rig):
    rig = make_rig(gpio_app(), main_dir=FIRMWARE / "mem32_gpio", allow_exit=True)
    rig.run_for(0.5)
    rig.stop()
    r = results(rig.console)
    assert r["set"] == [1, 1, 1], rig.console
    # OE set with OUT low, then OUT_SET, XOR, GPIO_OUT, CLR and Pin.value(1) (each 10 ms apart)
    want = [(0, 0), (0, 1), (10_000, 0), (20_000, 1), (30_000, 0), (30_000, 1)]
    assert [(t, v) for t, name, v in rig.plant.log if name == "out1"] == want, rig.plant.log
    assert r["pin_value"] == 1
    assert r["button"] == [0, 0, 1, 1], rig.console  # (read at 55, 80, 105, 130 ms; pressed 40..90 ms)
    assert r["gpio_in"] == 1  # (GP17's pad in GPIO_IN too, once its control was written)
    assert r["inverted"] == [0, hex(5 | 2 << 12 | 1 << 16)]
    assert r["unwired"] == [1, 1]
    assert r["funcsel"] == [5, 0x1F]  # (GP2 never chosen: FUNCSEL's reset value, NULL)
    assert r["unknown"] == [0, 0, 0]
    for addr in ("0xd0000100", "0x40054000"):
        assert sum(f"note: read of {addr}" in line for line in rig.console.splitlines()) == 1, rig.console


@pytest.mark.parametrize(
    ("identity", "over"),
    [(RP2040, 65535), (("esp32", "Generic ESP32 module with ESP32"), "duty_u16 must be from 0 to 65535")],
)
def test_a_duty_above_full_is_full_on_an_rp2_and_refused_on_an_esp32(make_rig, identity, over):
    """ports/rp2/machine_pwm.c limits duty_u16 to 65535; ports/esp32/machine_pwm.c raises."""
    app = bench_app("pwm_over_range", ROBOT, board="pins", identity=identity, wiring=WIRING, pins=PINS)
    rig = make_rig(app, main_dir=FIRMWARE / "pwm_over_range", allow_exit=True)
    rig.run_for(0.2)
    rig.stop()
    r = results(rig.console)
    assert r["over"] == over, rig.console
    assert r["negative"] == "duty_u16 must be from 0 to 65535", rig.console
