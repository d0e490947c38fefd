# A two-wheel robot on a Raspberry Pi Pico: TB6612FNG motor driver, N20 motors with Hall
# quadrature encoders, an HC-SR04 on the front, a start button. Press the button: it drives
# ahead, and turns away from anything closer than 25 cm. Plain MicroPython, as it goes on
# the board: `mpy-fil run rig.toml` and test_pico_bot.py run it against a simulated robot.
import time

from machine import PWM, Pin, time_pulse_us

# pins (GPn)
PWMA, AIN1, AIN2 = 16, 17, 18
PWMB, BIN1, BIN2 = 21, 20, 19
STBY = 22
ENC_LA, ENC_LB = 2, 3
ENC_RA, ENC_RB = 4, 5
TRIG, ECHO = 14, 15
BUTTON = 13
LED = 25

CRUISE = 0.6  # duty, 0..1
TURN = 0.45
STOP_CM = 25
LOOP_MS = 50


class Motor:
    """One TB6612FNG channel: two direction pins and a PWM."""

    def __init__(self, pwm, in1, in2):
        self.pwm = PWM(Pin(pwm))
        self.pwm.freq(20000)
        self.in1 = Pin(in1, Pin.OUT)
        self.in2 = Pin(in2, Pin.OUT)

    def speed(self, s):  # -1..1
        self.in1.value(1 if s > 0 else 0)
        self.in2.value(1 if s < 0 else 0)
        self.pwm.duty_u16(int(min(abs(s), 1.0) * 65535))


class Encoder:
    """Quadrature encoder counted on both edges of channel A (B gives the direction)."""

    def __init__(self, pin_a, pin_b):
        self.a = Pin(pin_a, Pin.IN)
        self.b = Pin(pin_b, Pin.IN)
        self.count = 0
        self.a.irq(trigger=Pin.IRQ_RISING | Pin.IRQ_FALLING, handler=self._edge)

    def _edge(self, pin):
        if self.a.value() == self.b.value():
            self.count -= 1
        else:
            self.count += 1


class HCSR04:
    """HC-SR04 ranger: a short TRIG pulse, then the ECHO pulse's length."""

    def __init__(self, trig, echo, timeout_us=30000):
        self.trig = Pin(trig, Pin.OUT)
        self.echo = Pin(echo, Pin.IN)
        self.timeout_us = timeout_us
        self.trig.value(0)

    def distance_cm(self):
        self.trig.value(0)
        time.sleep_us(5)
        self.trig.value(1)
        time.sleep_us(5)  # the datasheet says 10 us; most modules answer 5
        self.trig.value(0)
        t = time_pulse_us(self.echo, 1, self.timeout_us)
        if t < 0:
            return None  # no echo: nothing in range
        return t / 58.0


left = Motor(PWMA, AIN1, AIN2)
right = Motor(PWMB, BIN1, BIN2)
stby = Pin(STBY, Pin.OUT, value=1)
enc_l = Encoder(ENC_LA, ENC_LB)
enc_r = Encoder(ENC_RA, ENC_RB)
sonar = HCSR04(TRIG, ECHO)
button = Pin(BUTTON, Pin.IN, Pin.PULL_UP)
led = Pin(LED, Pin.OUT)

print("pico_bot: press start")
while button.value() == 1:
    time.sleep_ms(10)
print("pico_bot: go")

turning_until = None
while True:
    start = time.ticks_ms()
    led.toggle()
    d = sonar.distance_cm()
    if turning_until is not None:
        if time.ticks_diff(start, turning_until) >= 0:
            turning_until = None
            print("pico_bot: ahead", enc_l.count, enc_r.count)
    elif d is not None and d < STOP_CM:
        print("pico_bot: obstacle at %d cm, turning" % d)
        turning_until = time.ticks_add(start, 600)
    if turning_until is None:
        left.speed(CRUISE)
        right.speed(CRUISE)
    else:
        left.speed(-TURN)
        right.speed(TURN)
    time.sleep_ms(LOOP_MS - time.ticks_diff(time.ticks_ms(), start))
