"""machine.mem32/mem16/mem8 on an RP2040 (docs/shim.md, "Registers"): the PWM slices'
registers drive the plant as machine.PWM does, IO_BANK0's function select and overrides
and SIO's GPIO registers drive and read the pins, and any other address is named once."""

import pytest

from host.tests.conftest import FIRMWARE, bench_app, results

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
    assert r["from_pwm"] == [hex(3000), 5999]  # (duty_u16(32768) on TOP 5999: CC A = 3000)
    # freq(1000): TOP 124999 does not fit 16 bits, so div16 = ceil(16 * 125 MHz / (65534 * 1000))
    # = 31 and TOP = round(16 * 125 MHz / (31 * 1000)) - 1 (machine_pwm.c, mp_machine_pwm_freq_set)
    assert r["freq_regs"] == [64515, 31, 1000, 32768]
    notes = [line for line in rig.console.splitlines() if "0x40058000" in line]
    assert len(notes) == 1 and "[mpy-fil: note: read of 0x40058000" in notes[0], rig.console
