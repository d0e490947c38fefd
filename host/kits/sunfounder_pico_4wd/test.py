"""The SunFounder Pico-4WD car rig beside this file, exercised: a small firmware of this
test's own drives the four motors forwards (each held high on one input and pulsed low
on the other, as the car's drivers take it), counts the speed sensors' slots, ranges
ahead with the sonar on its servo, reads the grayscale channels and lights one of the
WS2812 LEDs by a PIO program; the plant's ground truth says whether the rig is wired as
the car is. Written by `mpy-fil init --kit sunfounder_pico_4wd`; run it with pytest."""

from pathlib import Path

RIG = Path(__file__).with_name("rig.toml")
FIRMWARE = """
import array, time
import rp2
from machine import ADC, PWM, Pin, time_pulse_us


@rp2.asm_pio(sideset_init=rp2.PIO.OUT_LOW, out_shiftdir=rp2.PIO.SHIFT_LEFT, autopull=True, pull_thresh=24)
def ws2812():
    label("bit")
    out(x, 1).side(0)[2]
    jmp(not_x, "zero").side(1)[1]
    jmp("bit").side(1)[4]
    label("zero")
    nop().side(0)[4]


def range_cm():
    trig.value(1)
    time.sleep_us(10)
    trig.value(0)
    return time_pulse_us(echo, 1, 30000) * 0.0343 / 2


slots = [0, 0]


def counted(i):
    def handler(pin):
        slots[i] += 1
    return handler


trig, echo = Pin(6, Pin.OUT, value=0), Pin(7, Pin.IN)
servo = PWM(Pin(18), freq=50, duty_u16=round(1500 / 20000 * 65535))  # straight ahead
for i, gpio in enumerate((8, 9)):
    Pin(gpio, Pin.IN, Pin.PULL_UP).irq(counted(i), Pin.IRQ_FALLING)
time.sleep_ms(300)
print("range_before", range_cm())
print("gray", [ADC(Pin(g)).read_u16() for g in (26, 27, 28)])
# (A, B) of each motor, left front, right front, left rear, right rear; forwards: the
# left ones pulse A low, the right ones B
motors = [[PWM(Pin(g), freq=20000, duty_u16=65535) for g in pair] for pair in ((17, 16), (15, 14), (13, 12), (11, 10))]
for pair, low in zip(motors, (0, 1, 0, 1)):
    pair[low].duty_u16(65535 - 40000)
time.sleep_ms(1000)
for pair in motors:
    for pwm in pair:
        pwm.duty_u16(65535)  # both high: braked
time.sleep_ms(300)
print("slots", slots[0], slots[1])
print("range_after", range_cm())
sm = rp2.StateMachine(0, ws2812, freq=8_000_000, sideset_base=Pin(19))
sm.active(1)
leds = array.array("I", [0] * 24)
leds[8] = 40 << 16  # (green, red, blue): green
sm.put(leds, 8)
time.sleep_ms(10)
print("done")
"""


def test_sunfounder_pico_4wd_rig_drives_counts_ranges_and_lights(make_rig, tmp_path):
    (tmp_path / "main.py").write_text(FIRMWARE)  # (the rig beside this file, with this firmware)
    (tmp_path / "rig.toml").write_text(RIG.read_text())
    rig = make_rig(str(tmp_path / "rig.toml"), allow_exit=True)
    start = rig.truth()
    before = float(rig.expect(r"range_before (\S+)\n").group(1))
    gray = rig.expect(r"gray \[(\d+), (\d+), (\d+)\]\n").groups()
    left, right = (int(v) for v in rig.expect(r"slots (\d+) (\d+)\n").groups())
    after = float(rig.expect(r"range_after (\S+)\n").group(1))
    rig.expect("done\n")
    truth = rig.truth()
    where = f"console:\n{rig.console}\nartefacts: {rig.artefacts}"
    moved = truth["x_m"] - start["x_m"]
    assert moved > 0.1 and abs(truth["y_m"] - start["y_m"]) < 0.005, (truth, where)
    for reading, x in ((before, start["x_m"]), (after, truth["x_m"])):
        assert abs(reading / 100 - (3.0 - 0.09 - x)) < 0.01, f"sonar {reading} cm at x {x}; {where}"
    assert [int(v) for v in gray] == [40000] * 3, f"grayscale over the white floor: {gray}; {where}"
    slot_m = 2 * 3.14159 * 0.033 / 20  # a slot a 20th of the wheel's rim
    for n, edges in ((left, truth["speed_l_edges"]), (right, truth["speed_r_edges"])):
        assert n == edges // 2, f"falling edges counted {n}, the disk's edges {edges}; {where}"
        assert abs(n * slot_m - moved) < 2 * slot_m, f"{n} slots against {moved:.3f} m; {where}"
    assert rig.plant.output("lights.led8") == 0x002800 and truth["lights_lit"] == 1, where
    assert truth["lights_timing_faults"] == 0, (truth, where)
