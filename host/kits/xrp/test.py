"""The SparkFun XRP (RP2350 controller) rig beside this file, exercised: a small
firmware of this test's own drives both motors by the board's pin names, counts the
encoders' edges and ranges the wall ahead; the plant's ground truth says whether the rig
is wired as the robot is. Written by `mpy-fil init --kit xrp`; run it with pytest."""

import math
from pathlib import Path

import pytest

RIG = Path(__file__).with_name("rig.toml")

FIRMWARE = """
import time
from machine import PWM, Pin, time_pulse_us

edges = [0, 0]


def counter(i):
    def count(_pin):
        edges[i] += 1

    return count


for i, side in enumerate("LR"):
    for ch in "AB":
        Pin("MOTOR_%s_ENCODER_%s" % (side, ch), Pin.IN).irq(counter(i), Pin.IRQ_RISING | Pin.IRQ_FALLING)
trig, echo = Pin("DISTANCE_TRIGGER", Pin.OUT, value=0), Pin("DISTANCE_ECHO", Pin.IN)


def range_cm():
    trig.value(1)
    time.sleep_us(10)
    trig.value(0)
    return time_pulse_us(echo, 1, 30000) * 0.0343 / 2


print("range_before", range_cm())
Pin("MOTOR_L_IN_2", Pin.OUT, value=0)  # a PWM each way, forwards as XRPLib's DualPWMMotor drives it:
Pin("MOTOR_R_IN_1", Pin.OUT, value=0)  # IN2 for the right motor, IN1 for the left (mounted mirrored)
speed = [PWM(Pin(name), freq=50, duty_u16=32768) for name in ("MOTOR_L_IN_1", "MOTOR_R_IN_2")]
time.sleep_ms(500)
for pwm in speed:
    pwm.duty_u16(0)
last = None
while last != edges:  # until the wheels have stopped
    last = list(edges)
    time.sleep_ms(100)
print("edges", edges[0], edges[1])
print("range_after", range_cm())
"""


def said(console: str) -> dict:
    return {w[0]: w[1:] for w in (line.split("] ", 1)[-1].split() for line in console.splitlines()) if w}


def test_xrp_rig_drives_counts_and_ranges(make_rig, tmp_path):
    (tmp_path / "main.py").write_text(FIRMWARE)  # (the rig beside this file, with this firmware)
    (tmp_path / "rig.toml").write_text(RIG.read_text())
    rig = make_rig(str(tmp_path / "rig.toml"), allow_exit=True)
    start = rig.truth()
    rig.expect(r"edges \d+ \d+\n")  # (the plant at the instant the firmware says its counts)
    truth = rig.truth()
    rig.expect(r"range_after \S+\n")
    console = rig.console
    where = f"console:\n{console}\nartefacts: {rig.artefacts}"
    got = said(console)
    assert "range_after" in got, f"the firmware did not finish; {where}"
    moved_m = truth["x_m"] - start["x_m"]
    assert moved_m > 0.05 and abs(truth["y_m"] - start["y_m"]) < 0.005, f"not straight ahead: {truth}; {where}"
    left, right = (int(v) for v in got["edges"])
    assert (left, right) == (abs(truth["enc_l_edges"]), abs(truth["enc_r_edges"])), f"edges vs {truth}; {where}"
    wheel_turns = left / 585  # 585 edges a wheel turn
    assert wheel_turns * math.pi * 0.060 == pytest.approx(moved_m, rel=0.02), where
    ahead_m = 3.0 - 0.10  # the room's east wall, less the rangefinder's place on the body
    for key, x in (("range_before", start["x_m"]), ("range_after", truth["x_m"])):
        assert abs(float(got[key][0]) / 100 - (ahead_m - x)) < 0.01, f"{key} vs x {x}; {where}"
