"""The Raspberry Pi Foundation's beginner library ``picozero`` (PyPI ``picozero`` 0.6.1,
pinned in host/core/drivers.txt, put in the firmware's ``lib/`` as Thonny installs it) run
unchanged on a Pico on a two-wheel chassis (hil_tests/firmware/picozero/rig.toml: the pins
as its documentation's recipes wire them). Each firmware is written as picozero's docs and
``docs/examples/`` write theirs (github.com/RaspberryPiFoundation/picozero; not copied), and
what it does is held to the plant's ground truth in virtual time (docs/kits.md, "Other
public robot code tried").

What it found in the harness:

- ``Button.when_pressed``: picozero's pin IRQ handler hands the callback on with
  ``micropython.schedule``; the scheduled callback ran at the next input change (the
  release, 300 ms later) where a board's wait runs it at its next pass, at the press
  (``ports/rp2/mphalport.c``, ``mp_hal_delay_ms``).
- ``pico_temp_sensor.temp``: ``ADC(4)`` is the RP2040's temperature sensor
  (``ports/rp2/machine_adc.c``, ``mp_machine_adc_make_new``), not GPIO 4: it read 0, 437
  degrees C."""

import shutil

import pytest

from host.core.drivers import DriverMissing, driver_folder
from host.core.paths import REPO
from host.tests.test_wokwi_more_parts import part

pytestmark = pytest.mark.hil

RIG = REPO / "hil_tests" / "firmware" / "picozero" / "rig.toml"
WALL_X_M = 3.0  # the room's east wall (room_w_m), ahead of the robot at its start
SONAR_X_M = 0.06  # the sonar ahead of the axle (the rig's mount)


def picozero(make_rig, tmp_path, main: str, **rig_options):
    """The rig, picozero in lib/ and ``main`` in a folder of their own."""
    try:
        library = driver_folder("picozero") / "picozero"
    except DriverMissing as e:
        pytest.skip(str(e))
    shutil.copytree(library, tmp_path / "lib" / "picozero")
    (tmp_path / "main.py").write_text(main)
    shutil.copy(RIG, tmp_path / "rig.toml")
    return make_rig(str(tmp_path / "rig.toml"), allow_exit=True, **rig_options)


def where(rig) -> str:
    return f"console:\n{rig.console}\nartefacts: {rig.artefacts}"


def timeline(rig, signal: str) -> list[tuple[int, object]]:
    """(t_us, value) of each change the firmware drove on ``signal``."""
    return [(t, v) for t, name, v in rig.recorder.events if name == signal]


def changes(events: list[tuple[int, object]], initial=0) -> list[tuple[int, object]]:
    """The (t_us, value) at which the value changed, from ``initial``."""
    out = []
    for t, v in events:
        if v != (out[-1][1] if out else initial):
            out.append((t, v))
    return out


def from_first_ms(events: list[tuple]) -> list[tuple]:
    """(ms, value) counted from the first event: picozero's import and set-up take a
    board's time with MCU time (MPYFIL_CPU), nothing with the CPU free."""
    return [(round((t - events[0][0]) / 1000), *rest) for t, *rest in events]


def on_time(got: list[tuple], want_ms: list[tuple]) -> bool:
    """``got`` (t_us, values...) has the values of ``want_ms`` (ms, values...), each at its
    time from the first within 0.5 ms and 1 % of it: with MCU time picozero's steps come
    0.1 to 0.5 ms late each (its Python between the waits), as on a board; with the CPU
    free, within 0.2 ms."""
    if [g[1:] for g in got] != [w[1:] for w in want_ms]:
        return False
    return all(abs(g[0] - got[0][0] - w[0] * 1000) <= 500 + 10 * w[0] for g, w in zip(got, want_ms))


ROBOT = """from picozero import Robot, DistanceSensor
from time import sleep

robot_rover = Robot(left=(14, 15), right=(12, 13))
ds = DistanceSensor(echo=2, trigger=3)

print("distance", ds.distance)
robot_rover.forward(t=1, wait=True)
print("forward done", ds.distance)
robot_rover.left(speed=0.5, t=0.5, wait=True)
print("left done")
robot_rover.stop()
sleep(0.5)
print("stopped")
"""


def test_robot_drives_forward_for_a_second_turns_left_and_stops_and_ranges_the_wall(make_rig, tmp_path):
    """Robot(left=(14, 15), right=(12, 13)) as robot_rover_square.py drives it (``t=``,
    ``wait=True``: a one-shot Timer turns the left motor off, a sleep the right one),
    DistanceSensor(echo=2, trigger=3) read before and after, each against the plant's truth."""
    start_x_m = 2.2  # (the rig's start_pose)
    rig = picozero(make_rig, tmp_path, ROBOT)
    first = float(rig.expect(r"distance ([\d.]+)\n").group(1))
    wall_m = WALL_X_M - start_x_m - SONAR_X_M
    assert abs(first - wall_m) < 0.01, f"expected the wall {wall_m:.3f} m ahead, read {first}; {where(rig)}"
    ahead = float(rig.expect(r"forward done ([\d.]+)\n").group(1))
    truth = rig.truth()
    assert 0.3 < truth["x_m"] - start_x_m < 0.42, f"a second at full speed (0.4 m/s, 40 ms lag): {truth}; {where(rig)}"
    assert abs(truth["theta_rad"]) < 0.01 and abs(truth["y_m"] - 1.0) < 0.005, f"straight: {truth}; {where(rig)}"
    wall_m = WALL_X_M - truth["x_m"] - SONAR_X_M
    assert abs(ahead - wall_m) < 0.02, f"expected the wall {wall_m:.3f} m ahead, read {ahead}; {where(rig)}"
    rig.expect("left done\n")
    turned = rig.truth()
    # half speed (0.2 m/s a wheel, opposite) on a 0.15 m track: 2.67 rad/s for 0.5 s, less the lag
    assert 1.0 < turned["theta_rad"] < 1.4, f"expected a left turn of about 1.3 rad, got {turned}; {where(rig)}"
    assert abs(turned["x_m"] - truth["x_m"]) < 0.02, f"on the spot: {truth} then {turned}; {where(rig)}"
    rig.expect("stopped\n")
    stopped = rig.truth()
    # stop() sets both inputs to 0: the bridge lets the motors coast (3 x 40 ms), so the
    # turn goes on by its rate times 0.12 s
    coast_rad = turned["w_rad_s"] * 0.12
    assert abs(stopped["w_rad_s"]) < 0.1 and abs(stopped["v_m_s"]) < 1e-3, f"stopped: {stopped}; {where(rig)}"
    assert abs(stopped["theta_rad"] - turned["theta_rad"] - coast_rad) < 0.03, (
        f"coasted {coast_rad:.3f} rad further: {turned} then {stopped}; {where(rig)}"
    )


BUTTON = """from picozero import Button, pico_led
from time import sleep, ticks_ms

button = Button(18)

def led_on():
    pico_led.on()
    print("pressed", ticks_ms())

def led_off():
    pico_led.off()
    print("released", ticks_ms())

button.when_pressed = led_on
button.when_released = led_off
sleep(1)
print("done")
"""


def test_button_when_pressed_and_when_released_run_at_the_press_and_the_release(make_rig, tmp_path):
    """button_led.py's callbacks: the rig's button pressed at 0.5 s, let go at 0.8 s; the
    Pico's LED (GP25) follows. picozero's IRQ handler schedules the callback
    (micropython.schedule); the sleep's next pass runs it at once."""
    rig = picozero(make_rig, tmp_path, BUTTON, record=True)
    rig.expect("done\n")
    assert "pressed 500\n" in rig.console and "released 800\n" in rig.console, (
        f"expected the callbacks at the press (500 ms) and the release (800 ms); {where(rig)}"
    )
    led = timeline(rig, "pico_led.in")
    assert [v for _t, v in led] == [0, 1, 0], f"expected off, on, off; got {led}; {where(rig)}"
    on_us, off_us = led[1][0], led[2][0]
    assert 500_000 <= on_us < 500_100 and 800_000 <= off_us < 800_100, f"at the press and release: {led}; {where(rig)}"


BLINK = """from picozero import pico_led
from time import sleep

pico_led.blink(on_time=0.1, off_time=0.2, n=3, wait=True)
print("blinked")
pico_led.blink(on_time=0.05, n=2)
print("blinking")
sleep(0.5)
print("done")
"""


def test_pico_led_blinks_n_times_waiting_and_in_the_background(make_rig, tmp_path):
    """pico_led.blink(..., n=3, wait=True) sleeps through its steps; blink(n=2) without
    wait steps on a one-shot Timer: the LED's level timeline has each edge at its time."""
    rig = picozero(make_rig, tmp_path, BLINK, record=True)
    rig.expect("done\n")
    edges = changes(timeline(rig, "pico_led.in"))
    want_ms = [(0, 1), (100, 0), (300, 1), (400, 0), (600, 1), (700, 0)]
    want_ms += [(900, 1), (950, 0), (1000, 1), (1050, 0)]
    assert on_time(edges, want_ms), (
        f"expected the LED's edges at {want_ms} ms, got {from_first_ms(edges)}; {where(rig)}"
    )


TUNE = """from picozero import Speaker

speaker = Speaker(5)

BEAT = 0.25

tune = [['c4', BEAT], ['e4', BEAT / 2], ['g4', BEAT], ['', BEAT / 2], [440, BEAT], [60, BEAT]]

try:
    speaker.play(tune)
finally:
    speaker.off()
print("played")
"""


def test_speaker_plays_a_tune_note_by_note(make_rig, tmp_path):
    """speaker_tune.py's ``speaker.play`` of [note, beats] pairs: note names, a rest, a
    frequency and a MIDI note, each sounded for 0.9 of its time, then 0.1 silent."""
    rig = picozero(make_rig, tmp_path, TUNE)
    rig.expect("played\n")
    beat = 0.25
    notes = [(262, beat), (330, beat / 2), (392, beat), (0, beat / 2), (440, beat), (261, beat)]
    want, t = [], 0.0
    for freq, length in notes:
        if freq:
            want.append((freq, round(t * 1000), round((t + 0.9 * length) * 1000)))
        t += length
    tones = part(rig, "speaker").tones  # [t_start_us, t_end_us, freq_hz]
    starts = on_time([(t0, freq) for t0, _t1, freq in tones], [(ms, freq) for freq, ms, _end in want])
    ends = on_time(
        [(tones[0][0], None)] + [(t1, freq) for _t0, t1, freq in tones], [(0, None)] + [(ms, f) for f, _s, ms in want]
    )
    tones = [(freq, start_ms, round((t1 - tones[0][0]) / 1000)) for start_ms, t1, freq in from_first_ms(tones)]
    assert starts and ends, f"expected the tones (Hz, from ms, to ms) {want}, got {tones}; {where(rig)}"
    assert rig.truth()["speaker_freq_hz"] == 0, f"silent at the end; {where(rig)}"


SENSORS = """from picozero import pico_temp_sensor, Pot, RGBLED
from time import sleep

pot = Pot(26)
print("temp", pico_temp_sensor.temp)
print("pot", pot.value, pot.voltage)

rgb = RGBLED(red=6, green=7, blue=8)
rgb.color = (255, 128, 0)
sleep(0.1)
print("rgb", rgb.color)
"""


def test_pico_temp_sensor_pot_and_rgbled_read_and_light_what_the_rig_has(make_rig, tmp_path):
    """pico_temp_sensor (ADC(4), the RP2040's sensor: 27 degrees C unwired), Pot(26) (the
    rig's knob at 0.3) and RGBLED(6, 7, 8).color as PWM duties."""
    rig = picozero(make_rig, tmp_path, SENSORS)
    temp_c = float(rig.expect(r"temp ([\d.-]+)\n").group(1))
    # 0.706 V as the 12-bit ADC reads it (876), through picozero's 27 - (v - 0.706) / 0.001721
    assert abs(temp_c - 27.0) < 0.1, f"expected the die at 27 degrees C, read {temp_c}; {where(rig)}"
    value, volts = map(float, rig.expect(r"pot ([\d.]+) ([\d.]+)\n").groups())
    assert abs(value - 0.3) < 2 / 4095 and abs(volts - 0.99) < 0.01, f"the knob at 0.3; {where(rig)}"
    rig.expect(r"rgb \(255, 128, 0\)\n")
    truth = rig.truth()
    got = (truth["rgb_r"], truth["rgb_g"], truth["rgb_b"])
    assert abs(got[0] - 1) < 1e-3 and abs(got[1] - 128 / 255) < 1e-3 and got[2] == 0, f"orange: {got}; {where(rig)}"


SERVO = """from picozero import Servo
from time import sleep

servo = Servo(1)

servo.min()
sleep(1)
print("min")
sleep(0.1)
servo.mid()
sleep(1)
print("mid")
sleep(0.1)
servo.max()
sleep(1)
print("max")
sleep(0.1)
servo.off()
sleep(0.1)
print("off")
"""


def test_servo_goes_to_min_mid_and_max_then_off(make_rig, tmp_path):
    """servo_move.py: Servo(1) at 50 Hz, 1 ms to 2 ms pulses (picozero's defaults), on the
    rig's SG90 (0.5 ms to 2.5 ms over 180 degrees): 45, 90 and 135 degrees; off() sends
    no pulse (a duty of 0)."""
    rig = picozero(make_rig, tmp_path, SERVO)
    for name, pulse_us in (("min", 1000), ("mid", 1500), ("max", 2000)):
        rig.expect(f"{name}\n")
        truth = rig.truth()
        angle_deg = (pulse_us - 500) / 2000 * 180
        # (picozero's duty is int(pulse / 20 ms * 65535): a little short of the pulse)
        said = f"{name}: expected {pulse_us} us, {angle_deg} degrees: {truth}; {where(rig)}"
        assert abs(truth["servo_pulse_us"] - pulse_us) < 1 and abs(truth["servo_angle_deg"] - angle_deg) < 0.5, said
    rig.expect("off\n")
    off = rig.truth()
    assert not off["servo_pulse_us"], f"off: expected no pulse, got {off}; {where(rig)}"


PULSE = """from picozero import LED
from time import sleep

led = LED(0)

led.pulse(fade_in_time=0.2, fade_out_time=0.2, n=1, wait=True)
print("pulsed")
led.pulse(fade_in_time=0.2, n=1)
print("pulsing")
sleep(0.5)
print("done")
"""


def test_led_pulse_fades_in_and_out_at_25_steps_a_second_waiting_and_on_a_timer(make_rig, tmp_path):
    """LED(0) is a PWMLED: pulse() steps its duty every 1/25 s (fps), from 0 up to below
    full and back down, then off; with wait=False a one-shot Timer makes each step."""
    rig = picozero(make_rig, tmp_path, PULSE, record=True)
    rig.expect("done\n")
    # each step's value as picozero computes it (i / fps / fade_time), as duty_u16
    fade = [i * (1 / 25) / 0.2 for i in range(5)]
    steps = [int(65535 * v) for v in fade + [1 - v for v in fade]] + [0]  # (then off)
    want = [(start_ms + 40 * k, duty) for start_ms in (0, 400) for k, duty in enumerate(steps)]
    want = [(t - 40, v) for t, v in changes(want)]  # (from the first step up, 40 ms in)
    got = changes(timeline(rig, "led_0.in"))
    assert on_time(got, want), f"expected (ms, duty_u16) {want}, got {from_first_ms(got)}; {where(rig)}"


TOUCH = """from picozero import TouchSensor, pico_led
from time import sleep, ticks_ms

touch = TouchSensor(16)

def started():
    pico_led.on()
    print("touched", ticks_ms(), touch.is_touched)

touch.when_touch_starts = started
touch.when_touch_ends = pico_led.off
sleep(0.6)
print("done", touch.is_touched)
"""


def test_a_touch_sensor_on_its_pull_down_lights_the_led_while_touched(make_rig, tmp_path):
    """touch_sensor_callbacks.py: TouchSensor (a Button with pull_up=False: the pin pulled
    down, high while touched), touched from 0.3 s to 0.4 s."""
    rig = picozero(make_rig, tmp_path, TOUCH, record=True)
    rig.expect("done False\n")
    assert "touched 300 True\n" in rig.console, f"expected the callback at the touch, 300 ms; {where(rig)}"
    led = [(round(t / 1000), v) for t, v in changes(timeline(rig, "pico_led.in"))]
    assert led == [(300, 1), (400, 0)], f"expected the LED lit from 300 to 400 ms, got {led}; {where(rig)}"
