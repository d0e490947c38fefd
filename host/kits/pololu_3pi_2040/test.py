"""The Pololu 3pi+ 2040 rig beside this file, exercised: a small firmware of this test's
own drives both motors, counts the encoders' edges, asks the IMU's two chips who they
are, times each line sensor's discharge with its emitters on and lights the six RGB LEDs;
the plant's ground truth says whether the rig is wired as the robot is. Written by
`mpy-fil init --kit pololu_3pi_2040`; run it with pytest."""

import math
from pathlib import Path

import pytest

RIG = Path(__file__).with_name("rig.toml")
FIRMWARE = """
import time
from machine import I2C, PWM, SPI, Pin, time_pulse_us

edges = [0, 0]


def counter(i):
    def count(_pin):
        edges[i] += 1

    return count


for i, pins in enumerate(((12, 13), (8, 9))):
    for gpio in pins:
        Pin(gpio, Pin.IN).irq(counter(i), Pin.IRQ_RISING | Pin.IRQ_FALLING)
i2c = I2C(0, scl=Pin(5), sda=Pin(4), freq=400_000)
print("who", i2c.readfrom_mem(0x6B, 0x0F, 1)[0], i2c.readfrom_mem(0x1E, 0x0F, 1)[0])
Pin(26, Pin.OUT, value=1)  # the line sensors' emitters
line = []
for gpio in (22, 21, 20, 19, 18):  # left to right
    sensor = Pin(gpio, Pin.OUT, value=1)  # charge ...
    time.sleep_us(10)
    sensor.init(Pin.IN)  # ... let go, and time the discharge
    line.append(time_pulse_us(sensor, 1, 1024))
print("line", *line)
sck = Pin(6)  # the LEDs' clock, SPI0's only while they are written (GP3 MOSI is the display's too)
spi = SPI(0, baudrate=20_000_000, sck=sck, mosi=Pin(3))
spi.write(bytes(4) + bytes((0xFF, 0, 0, 255)) * 6 + bytes((0xFF,)))  # start frame, six red LEDs, end
sck.init(Pin.OUT, value=0)
Pin(10, Pin.OUT, value=0)  # forwards
Pin(11, Pin.OUT, value=0)
speed = [PWM(Pin(gpio), freq=20833, duty_u16=16384) for gpio in (15, 14)]
time.sleep_ms(500)
for pwm in speed:
    pwm.duty_u16(0)
last = None
while last != edges:  # until the wheels have stopped
    last = list(edges)
    time.sleep_ms(100)
print("edges", edges[0], edges[1])
"""


def said(console: str) -> dict:
    return {w[0]: w[1:] for w in (line.split("] ", 1)[-1].split() for line in console.splitlines()) if w}


def test_pololu_3pi_2040_rig_drives_counts_and_finds_its_imu(make_rig, tmp_path):
    (tmp_path / "main.py").write_text(FIRMWARE)  # (the rig beside this file, with this firmware)
    (tmp_path / "rig.toml").write_text(RIG.read_text())
    rig = make_rig(str(tmp_path / "rig.toml"), allow_exit=True)
    start = rig.truth()
    rig.expect(r"line[ \d-]+\n")
    discharged = rig.truth()["line_discharge_us"]  # (the plant as the reads ended: each read's time)
    rig.expect(r"edges \d+ \d+\n")  # (the plant at the instant the firmware says its counts)
    truth, console = rig.truth(), rig.console
    where = f"console:\n{console}\nartefacts: {rig.artefacts}"
    got = said(console)
    assert "edges" in got, f"the firmware did not finish; {where}"
    assert got["who"] == ["108", "61"], f"LSM6DSO WHO_AM_I 0x6C, LIS3MDL 0x3D; {where}"
    assert [abs(int(v) - us) <= 10 for v, us in zip(got["line"], discharged)] == [True] * 5, (
        f"expected each line sensor's time within 10 us of the plant's discharge, read {got['line']}, "
        f"discharged {discharged}; {where}"
    )
    assert truth["rgb_leds_lit"] == 6 and truth["rgb_leds_faults"] == 0, f"six LEDs lit: {truth}; {where}"
    moved_m = truth["x_m"] - start["x_m"]
    assert moved_m > 0.02 and abs(truth["y_m"] - start["y_m"]) < 0.005, f"not straight ahead: {truth}; {where}"
    left, right = (int(v) for v in got["edges"])
    assert (left, right) == (abs(truth["enc_l_edges"]), abs(truth["enc_r_edges"])), f"edges vs {truth}; {where}"
    per_turn = 12 * 29.86  # edges a wheel turn
    assert left / per_turn * math.pi * 0.032 == pytest.approx(moved_m, rel=0.02), where
