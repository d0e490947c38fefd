"""The Cytron Maker Pi RP2040 rig beside this file, exercised: a small firmware of this
test's own waits for button 1, drives both motors as Cytron's example does, ranges the wall
ahead on Grove 2 and lights the two NeoPixels; the plant's ground truth says whether the
rig is wired as the robot is. Written by `mpy-fil init --kit cytron_maker_pi_rp2040`."""

from pathlib import Path

RIG = Path(__file__).with_name("rig.toml")
FIRMWARE = """
import time
from machine import PWM, Pin, time_pulse_us
from neopixel import NeoPixel

button = Pin(20, Pin.IN, Pin.PULL_UP)
trig, echo = Pin(3, Pin.OUT, value=0), Pin(2, Pin.IN)
pixels = NeoPixel(Pin(18), 2)


def range_cm():
    trig.value(1)
    time.sleep_us(10)
    trig.value(0)
    return time_pulse_us(echo, 1, 30000) * 0.0343 / 2


while button.value():
    time.sleep_ms(10)
print("range_before", range_cm())
m1a, m1b, m2a, m2b = (PWM(Pin(gpio), freq=50, duty_u16=0) for gpio in (8, 9, 10, 11))
m1b.duty_u16(30000)  # forwards, as Cytron's example drives them
m2b.duty_u16(30000)
time.sleep_ms(500)
m1b.duty_u16(0)
m2b.duty_u16(0)
time.sleep_ms(500)
pixels[0] = (0, 40, 0)
pixels[1] = (40, 0, 0)
pixels.write()
print("range_after", range_cm())
"""


def test_cytron_maker_pi_rp2040_rig_waits_drives_ranges_and_lights(make_rig, tmp_path):
    (tmp_path / "main.py").write_text(FIRMWARE)  # (the rig beside this file, with this firmware)
    text = RIG.read_text().replace('name = "button_1"\n', 'name = "button_1"\npresses = [[0.2, 0.3]]\n')
    (tmp_path / "rig.toml").write_text(text)
    rig = make_rig(str(tmp_path / "rig.toml"), allow_exit=True)
    start = rig.truth()
    before = float(rig.expect(r"range_before (\S+)\n").group(1))
    assert rig.t_us >= 200_000, "the firmware waited for button 1 (pressed at 0.2 s)"
    after = float(rig.expect(r"range_after (\S+)\n").group(1))
    truth = rig.truth()
    where = f"console:\n{rig.console}\nartefacts: {rig.artefacts}"
    moved_m = truth["x_m"] - start["x_m"]
    assert moved_m > 0.02 and abs(truth["y_m"] - start["y_m"]) < 0.005, f"not straight ahead: {truth}; {where}"
    ahead_m = 3.0 - 0.08  # the room's east wall, less the sonar's place on the body
    assert abs(before / 100 - (ahead_m - start["x_m"])) < 0.01, where
    assert abs(after / 100 - (ahead_m - truth["x_m"])) < 0.01, where
    leds = [rig.plant.output(f"rgb.led{i}") for i in range(2)]
    assert leds == [0x002800, 0x280000], f"{[hex(v) for v in leds]}; {where}"
