"""The Kitronik Pico Autonomous Robotics Platform rig beside this file, exercised: a small
firmware of this test's own waits for the button, drives both motors forwards, ranges
ahead and behind with the two ultrasonic sensors and lights the ZIP LEDs' first pixel;
the plant's ground truth says whether the rig is wired as the buggy is. Written by
`mpy-fil init --kit kitronik_buggy`; run it with pytest."""

from pathlib import Path

RIG = Path(__file__).with_name("rig.toml")
FIRMWARE = """
import time
from machine import PWM, Pin, time_pulse_us
from neopixel import NeoPixel

button = Pin(0, Pin.IN, Pin.PULL_DOWN)  # pressed is high


def range_cm(trig, echo):
    trig, echo = Pin(trig, Pin.OUT, value=0), Pin(echo, Pin.IN)
    trig.value(1)
    time.sleep_us(10)
    trig.value(0)
    return time_pulse_us(echo, 1, 30000) * 0.0343 / 2


while not button.value():
    time.sleep_ms(10)
print("ranges_before", range_cm(14, 15), range_cm(3, 2))
motors = [PWM(Pin(gpio), freq=100, duty_u16=0) for gpio in (20, 19, 6, 7)]
motors[0].duty_u16(40000)  # both forwards
motors[2].duty_u16(40000)
time.sleep_ms(500)
motors[0].duty_u16(0)
motors[2].duty_u16(0)
time.sleep_ms(500)
zip_leds = NeoPixel(Pin(18), 4)
zip_leds[0] = (0, 0, 40)
zip_leds.write()
print("ranges_after", range_cm(14, 15), range_cm(3, 2))
"""


def test_kitronik_buggy_rig_waits_drives_and_ranges_both_ways(make_rig, tmp_path):
    (tmp_path / "main.py").write_text(FIRMWARE)  # (the rig beside this file, with this firmware)
    text = RIG.read_text().replace('name = "button"\n', 'name = "button"\npresses = [[0.2, 0.3]]\n')
    (tmp_path / "rig.toml").write_text(text)
    rig = make_rig(str(tmp_path / "rig.toml"), allow_exit=True)
    start = rig.truth()
    front0, rear0 = (float(v) for v in rig.expect(r"ranges_before (\S+) (\S+)\n").groups())
    assert rig.t_us >= 200_000, "the firmware waited for the button (pressed at 0.2 s)"
    front1, rear1 = (float(v) for v in rig.expect(r"ranges_after (\S+) (\S+)\n").groups())
    truth = rig.truth()
    where = f"console:\n{rig.console}\nartefacts: {rig.artefacts}"
    assert truth["x_m"] - start["x_m"] > 0.02 and abs(truth["y_m"] - start["y_m"]) < 0.005, (truth, where)
    for (front, rear), x in (((front0, rear0), start["x_m"]), ((front1, rear1), truth["x_m"])):
        assert abs(front / 100 - (3.0 - 0.08 - x)) < 0.01, f"front {front} cm at x {x}; {where}"
        assert abs(rear / 100 - (x - 0.08)) < 0.01, f"rear {rear} cm at x {x}; {where}"
    assert rig.plant.output("zip.led0") == 0x000028, where
