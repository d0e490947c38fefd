"""The Keyestudio Beetlebot rig beside this file, exercised: a small firmware of this test's
own, in the style of Keyestudio's tutorials, drives both motors forwards (direction pins
low, PWM duty 800 of 1023), ranges the wall ahead with the sonar on the servo (looking
ahead: duty 77 at 50 Hz), reads the two line trackers, lights the four WS2812s, beeps and
draws an arrow on the HT16K33 matrix;
the plant's ground truth says whether the rig is wired as the robot is. Written by
`mpy-fil init --kit keyestudio_beetlebot`."""

from pathlib import Path

RIG = Path(__file__).with_name("rig.toml")
FIRMWARE = """
import time
import neopixel
from machine import I2C, PWM, Pin, time_pulse_us

servo = PWM(Pin(4), freq=50)
servo.duty(77)
trig, echo = Pin(5, Pin.OUT, 0), Pin(18, Pin.IN, 0)
left, right = Pin(17, Pin.IN), Pin(16, Pin.IN)
np = neopixel.NeoPixel(Pin(14, Pin.OUT), 4)


def range_cm():
    trig.value(1)
    time.sleep_us(10)
    trig.value(0)
    return time_pulse_us(echo, 1, 30000) * 0.0343 / 2


time.sleep_ms(500)
print("range_before", range_cm())
print("trackers", left.value(), right.value())
dir_r, pwm_r = Pin(32, Pin.OUT), PWM(Pin(25), freq=50, duty=0)
dir_l, pwm_l = Pin(33, Pin.OUT), PWM(Pin(26), freq=50, duty=0)
dir_r.value(0)
dir_l.value(0)
pwm_r.duty(800)
pwm_l.duty(800)
time.sleep_ms(500)
pwm_r.duty(0)
pwm_l.duty(0)
time.sleep_ms(500)
for i in range(4):
    np[i] = (0, 40, 0) if i % 2 else (40, 0, 0)
np.write()
beeper = PWM(Pin(2), freq=440, duty=512)
time.sleep_ms(100)
beeper.duty(0)
i2c = I2C(scl=Pin(22), sda=Pin(21))
for command in (0x21, 0x81, 0xE2):  # the matrix: oscillator on, display on, dimming 2
    i2c.writeto(0x70, bytes([command]))
arrow = b"\\x18\\x24\\x42\\x99\\x24\\x42\\x81\\x00"  # one byte a row, bit 0 the left column
i2c.writeto(0x70, bytes([0]) + bytes(b for row in arrow for b in (row, 0)))
print("range_after", range_cm())
"""


def test_keyestudio_beetlebot_rig_drives_ranges_and_lights(make_rig, tmp_path):
    (tmp_path / "main.py").write_text(FIRMWARE)  # (the rig beside this file, with this firmware)
    (tmp_path / "rig.toml").write_text(RIG.read_text())
    rig = make_rig(str(tmp_path / "rig.toml"), allow_exit=True)
    start = rig.truth()
    before = float(rig.expect(r"range_before (\S+)\n").group(1))
    trackers = rig.expect(r"trackers (\d) (\d)\n").groups()
    after = float(rig.expect(r"range_after (\S+)\n").group(1))
    truth = rig.truth()
    where = f"console:\n{rig.console}\nartefacts: {rig.artefacts}"
    moved_m = truth["x_m"] - start["x_m"]
    assert moved_m > 0.05 and abs(truth["y_m"] - start["y_m"]) < 0.005, f"not straight ahead: {truth}; {where}"
    ahead_m = 3.0 - 0.07  # the room's east wall, less the sonar's place on the body
    assert abs(before / 100 - (ahead_m - start["x_m"])) < 0.01, where
    assert abs(after / 100 - (ahead_m - truth["x_m"])) < 0.01, where
    assert trackers == ("0", "0"), f"the trackers over the white floor read 0: {trackers}; {where}"
    leds = [rig.plant.output(f"leds.led{i}") for i in range(4)]
    assert leds == [0x280000, 0x002800, 0x280000, 0x002800], f"{[hex(v) for v in leds]}; {where}"
    assert truth["buzzer_tones"] >= 1, f"the buzzer played no tone: {truth}; {where}"
    assert (truth["matrix_on"], truth["matrix_lit_px"]) == (1, 16), f"the matrix's arrow: {truth}; {where}"
