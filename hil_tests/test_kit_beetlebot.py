"""The Keyestudio Beetlebot (ESP32; host/kits/keyestudio_beetlebot, docs/kits.md) run with
firmware in the style of Keyestudio's MicroPython tutorials (their flat scripts: pins by
number, a PWM made again before each drive, the sonar's echo polled with ``ticks_us``; not
a copy): what their code did that the harness once got wrong, each held to the plant's
ground truth in virtual time.

- A motor's direction pin (``Pin(32, Pin.OUT)``, a DRV8833's IN1) held high drove the
  plant's duty input at 1 of 65535, not at 100 %: "back" (high, duty 250) went forwards.
- ``Pin(5, Pin.OUT, 0)``: the pull 0 (no pull; any int is taken, its bits the pulls:
  ``ports/esp32/machine_pin.c``) was ``ValueError: invalid pull 0``.
- ``adc.width(ADC.WIDTH_10BIT)``, then ``adc.read()`` 0..1023: the ESP32's widths were not
  there (``AttributeError``), and ``read()`` was 12 bits whatever the width.
- ``pwm.deinit()`` then ``pwm.duty(0)``: an ESP32 raises ``RuntimeError`` ("PWM inactive";
  from 1.26 "PWM is inactive": ``ports/esp32/machine_pwm.c``, ``pwm_is_active``); the loop
  took it."""

import pytest

from host.kits import kit

pytestmark = pytest.mark.hil

MOTORS = """
from machine import Pin,PWM
import time

# right wheel
pin1=Pin(32,Pin.OUT)
pin2=PWM(Pin(25),freq=50,duty=0)
# left wheel
pin3=Pin(33,Pin.OUT)
pin4=PWM(Pin(26),freq=50,duty=0)

def car_forward():
  pin1.value(0)
  pin2.duty(1000)
  pin3.value(0)
  pin4.duty(1000)

def car_back():
  pin1.value(1)
  pin2.duty(250)
  pin3.value(1)
  pin4.duty(250)

def car_stop():
  pin2.deinit()
  pin4.deinit()
  pin1.value(0)
  pin2.duty(0)
  pin3.value(0)
  pin4.duty(0)
"""


def beetle(make_rig, tmp_path, main: str):
    """The kit's rig and ``main`` in a folder of their own."""
    (tmp_path / "rig.toml").write_text((kit("keyestudio_beetlebot").folder / "rig.toml").read_text())
    (tmp_path / "main.py").write_text(main)
    return make_rig(str(tmp_path / "rig.toml"), allow_exit=True)


def where(rig) -> str:
    return f"console:\n{rig.console}\nartefacts: {rig.artefacts}"


def test_a_direction_pin_held_high_on_a_drv8833_drives_the_wheels_backwards(make_rig, tmp_path):
    rig = beetle(
        make_rig,
        tmp_path,
        MOTORS + "car_forward()\ntime.sleep(1)\nprint('forward')\ncar_back()\ntime.sleep(1)\nprint('back')\n",
    )
    rig.expect("forward\n")
    ahead = rig.truth()
    rig.expect("back\n")
    back = rig.truth()
    assert ahead["v_m_s"] > 0.1 and ahead["x_m"] > 0.6, f"forwards at duty 1000: {ahead}; {where(rig)}"
    # high and duty 250: the DRV8833 drives backwards for the rest of each period, 1 - 250/1023
    # (the tutorial's "Go back: HIGH, 50" of 255), against 1000/1023 forwards
    ratio = -back["v_m_s"] / ahead["v_m_s"]
    assert back["x_m"] < ahead["x_m"] and 0.6 < ratio < 0.85, (
        f"backwards at 0.6..0.85 of the forward speed: {ratio:.3f} ({ahead['v_m_s']:.3f} then "
        f"{back['v_m_s']:.3f} m/s, x {ahead['x_m']:.3f} then {back['x_m']:.3f} m); {where(rig)}"
    )
    assert abs(back["theta_rad"]) < 0.01, f"both wheels alike: heading {back['theta_rad']}; {where(rig)}"


def test_pins_made_with_pull_0_range_the_wall_by_a_polled_echo(make_rig, tmp_path):
    rig = beetle(
        make_rig,
        tmp_path,
        """from machine import Pin
import time

trigPin=Pin(5,Pin.OUT,0)
echoPin=Pin(18,Pin.IN,0)
soundVelocity=340

def getSonar():
    trigPin.value(1)
    time.sleep_us(10)
    trigPin.value(0)
    while not echoPin.value():
        pass
    pingStart=time.ticks_us()
    while echoPin.value():
        pass
    pingStop=time.ticks_us()
    pingTime=time.ticks_diff(pingStop,pingStart)
    distance=pingTime*soundVelocity//2//10000
    return int(distance)

for i in range(3):
    time.sleep_ms(100)
    print('Distance: ',getSonar(),'cm')
""",
    )
    for _ in range(3):
        cm = int(rig.expect(r"Distance:  (\d+) cm\n").group(1))
        true_m = rig.truth()["sonar_ping_range_m"]
        # (their 340 m/s against the plant's 343, and whole centimetres rounded down)
        expected = true_m * 100 * 340 / 343 if true_m else None
        assert expected and abs(cm - expected) < 1.5, f"read {cm} cm, the wall at {true_m} m; {where(rig)}"


def test_the_esp32_adc_width_sets_what_read_returns(make_rig, tmp_path):
    rig = beetle(
        make_rig,
        tmp_path,
        """from machine import ADC, Pin
import time
adc1 = ADC(Pin(34))
adc1.atten(ADC.ATTN_11DB)
print('twelve', adc1.read())
adc1.width(ADC.WIDTH_10BIT)
adc2 = ADC(Pin(35))
adc2.atten(ADC.ATTN_11DB)
adc2.width(ADC.WIDTH_10BIT)
print('ADC Value1:', adc1.read(), 'ADC Value2:', adc2.read(), adc1.read_u16())
try:
    adc1.width(8)
except ValueError as e:
    print('width 8:', e)
""",
    )
    twelve = int(rig.expect(r"twelve (\d+)\n").group(1))
    one, two, u16 = (int(v) for v in rig.expect(r"ADC Value1: (\d+) ADC Value2: (\d+) (\d+)\n").groups())
    left, right = rig.plant.output("light_l.ao"), rig.plant.output("light_r.ao")
    assert twelve == left >> 4, f"12 bits at boot: {twelve}, the plant's {left} >> 4 = {left >> 4}; {where(rig)}"
    assert (one, two, u16) == (left >> 6, right >> 6, left), (
        f"10 bits after width(WIDTH_10BIT): read {one}, {two} (read_u16 {u16}), "
        f"the plant's {left}, {right} >> 6 = {left >> 6}, {right >> 6}; {where(rig)}"
    )
    assert rig.expect(r"width 8: (.+)\n").group(1) in ("invalid bits", "invalid bit-width"), where(rig)


def test_a_deinit_pwm_refuses_its_duty_as_an_esp32_does_and_a_new_one_drives(make_rig, tmp_path):
    rig = beetle(
        make_rig,
        tmp_path,
        MOTORS
        + """car_forward()
time.sleep(1)
try:
    car_stop()
except RuntimeError as e:
    print('stop:', e)
time.sleep(1)
print('stopped')
pin2=PWM(Pin(25),freq=50)
pin4=PWM(Pin(26),freq=50)
car_forward()
time.sleep(1)
print('again')
""",
    )
    said = rig.expect(r"stop: (.+)\n").group(1)
    assert said in ("PWM inactive", "PWM is inactive"), f"car_stop() said {said!r}; {where(rig)}"
    rig.expect("stopped\n")
    stopped = rig.truth()
    assert abs(stopped["v_m_s"]) < 0.01, f"deinit holds the PWM pins low: the wheels stop; {stopped}; {where(rig)}"
    rig.expect("again\n")
    again = rig.truth()
    moved = again["x_m"] - stopped["x_m"]
    assert again["v_m_s"] > 0.1 and moved > 0.1, f"PWM() made again drives: {again}; {where(rig)}"
