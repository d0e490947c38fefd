# ruff: noqa: F821  (a PIO body's names exist only while rp2.asm_pio assembles it)
# A small board library in the style of SunFounder's Pico-4WD library (pico_rdp.py and
# pico_4wd.py of github.com/sunfounder/pico_4wd_car; not a copy): its imports, its habits
# (a Timer with no id, counting on falling edges in a soft IRQ, the motors' inputs held
# high and pulsed low, the LEDs put to a PIO state machine 24 words at a time) and its
# quirks (time_pulse_us(echo, Pin.on): a function as the level).
import array
import math
import time
from machine import ADC, PWM, Pin, Timer, time_pulse_us
from rp2 import PIO, StateMachine, asm_pio


def scale(x, in_min, in_max, out_min, out_max):
    return (x - in_min) * (out_max - out_min) / (in_max - in_min) + out_min


class Wheel:
    def __init__(self, pin_a, pin_b, dir=1):
        self.a = PWM(Pin(pin_a, Pin.OUT))
        self.b = PWM(Pin(pin_b, Pin.OUT))
        self.a.freq(20000)
        self.b.freq(20000)
        self.dir = dir
        self.power = 0

    def set_power(self, power):
        self.power = power
        dir = (-1 if power < 0 else 1) * self.dir
        value = 0 if power == 0 else int(scale(abs(power), 0, 100, 20, 100) / 100 * 0xFFFF)
        value = 0xFFFF - value
        if power == 0:
            self.a.duty_u16(0xFFFF)
            self.b.duty_u16(0xFFFF)
        elif dir > 0:
            self.a.duty_u16(value)
            self.b.duty_u16(0xFFFF)
        else:
            self.a.duty_u16(0xFFFF)
            self.b.duty_u16(value)


class Sonar:
    def __init__(self, trig, echo):
        self.trig = Pin(trig, Pin.OUT)
        self.echo = Pin(echo, Pin.IN)

    def distance(self):
        self.trig.high()
        time.sleep_us(10)
        self.trig.low()
        width = time_pulse_us(self.echo, Pin.on) / 10000
        return width / 2.0 * 340.0


class Slots:
    PERIOD = 200

    def __init__(self, pin1, pin2):
        self.left = 0
        self.right = 0
        self.speed = 0
        self.total = [0, 0]
        self.l_pin = Pin(pin1, Pin.IN, Pin.PULL_UP)
        self.r_pin = Pin(pin2, Pin.IN, Pin.PULL_UP)
        self.l_pin.irq(trigger=Pin.IRQ_FALLING, handler=self.on_left)
        self.r_pin.irq(trigger=Pin.IRQ_FALLING, handler=self.on_right)
        self.tim = Timer()
        self.tim.init(period=self.PERIOD, mode=Timer.PERIODIC, callback=self.on_timer)

    def on_left(self, ch):
        if self.l_pin.value() == 0:
            self.left += 1

    def on_right(self, ch):
        if self.r_pin.value() == 0:
            self.right += 1

    def on_timer(self, ch):
        rim = 2.0 * math.pi * 3.3
        left = self.left * (1000 / self.PERIOD) / 20.0 * rim
        right = self.right * (1000 / self.PERIOD) / 20.0 * rim
        self.speed = round((left + right) / 2, 2)
        self.total[0] += self.left
        self.total[1] += self.right
        self.left = 0
        self.right = 0


@asm_pio(sideset_init=PIO.OUT_LOW, out_shiftdir=PIO.SHIFT_LEFT, autopull=True, pull_thresh=24)
def _ws2812():
    label("bitloop")
    out(x, 1).side(0)[2]
    jmp(not_x, "do_zero").side(1)[1]
    jmp("bitloop").side(1)[4]
    label("do_zero")
    nop().side(0)[4]


class Lights:
    def __init__(self, pin, num):
        self.num = num
        self.sm = StateMachine(0, _ws2812, freq=8000000, sideset_base=pin)
        self.sm.active(1)
        self.buf = array.array("I", [0 for _ in range(num)])

    def __setitem__(self, i, color):
        self.buf[i] = (color[0] << 8) + (color[1] << 16) + color[2]

    def show(self):
        self.sm.put(self.buf, 8)


wheels = [Wheel(17, 16, dir=1), Wheel(15, 14, dir=-1), Wheel(13, 12, dir=1), Wheel(11, 10, dir=-1)]
sonar = Sonar(6, 7)
slots = Slots(8, 9)
lights = Lights(Pin(19, Pin.OUT), 24)
gray = [ADC(Pin(26)), ADC(Pin(27)), ADC(Pin(28))]


def drive(*powers):
    for i, wheel in enumerate(wheels):
        wheel.set_power(powers[i])


def all_lights(color):
    for i in range(24):
        lights[i] = color
    lights.show()
