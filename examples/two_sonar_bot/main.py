# A two-wheel robot on a Raspberry Pi Pico with an HC-SR04 at the front and another at the
# back: TB6612FNG motor driver, N20 motors with Hall quadrature encoders, a start button
# to 3V3 on a pull-down. Press the button: it drives ahead until something is 30 cm in
# front, backs away until the wall behind is 25 cm off, and stops. Plain MicroPython, as
# it goes on the board: `mpy-fil run rig.toml` and test_two_sonar_bot.py run it against a
# simulated robot.
import time

from machine import PWM, Pin, time_pulse_us

# pins (GPn)
PWMA, AIN1, AIN2 = 16, 17, 18
PWMB, BIN1, BIN2 = 21, 20, 19
STBY = 22
ENC_LA, ENC_LB = 2, 3
ENC_RA, ENC_RB = 4, 5
TRIG_F, ECHO_F = 14, 15
TRIG_R, ECHO_R = 10, 11
BUTTON = 13
LED = 25

SPEED = 0.5  # duty, 0..1
FRONT_STOP_CM = 30
REAR_STOP_CM = 25
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
    """Quadrature encoder counted on both edges of channel A (B gives the direction).

    A hard IRQ: its handler runs at the edge, even while the main program waits in
    time_pulse_us for an echo (up to 30 ms). A scheduled one would run after the read
    returns, and read A and B as they are then, not at its edge: the count drifts, and
    edges past the scheduler's queue (8 on an RP2040) are lost."""

    def __init__(self, pin_a, pin_b):
        self.a = Pin(pin_a, Pin.IN)
        self.b = Pin(pin_b, Pin.IN)
        self.count = 0
        self.a.irq(trigger=Pin.IRQ_RISING | Pin.IRQ_FALLING, handler=self._edge, hard=True)

    def _edge(self, pin):
        if self.a.value() == self.b.value():
            self.count -= 1
        else:
            self.count += 1


class HCSR04:
    """HC-SR04 ranger: a 10 us TRIG pulse, then the ECHO pulse's length."""

    def __init__(self, trig, echo, timeout_us=30000):
        self.trig = Pin(trig, Pin.OUT)
        self.echo = Pin(echo, Pin.IN)
        self.timeout_us = timeout_us
        self.trig.value(0)

    def distance_cm(self):
        self.trig.value(0)
        time.sleep_us(2)
        self.trig.value(1)
        time.sleep_us(10)
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
front = HCSR04(TRIG_F, ECHO_F)
rear = HCSR04(TRIG_R, ECHO_R)
led = Pin(LED, Pin.OUT)

pressed_ms = None


def on_press(pin):
    global pressed_ms
    if pressed_ms is None:
        pressed_ms = time.ticks_ms()


button = Pin(BUTTON, Pin.IN, Pin.PULL_DOWN)
button.irq(trigger=Pin.IRQ_RISING, handler=on_press)


def drive(s):
    left.speed(s)
    right.speed(s)


boot_ms = time.ticks_ms()
print("two_sonar_bot: press start")
while pressed_ms is None:
    led.toggle()
    time.sleep_ms(LOOP_MS)
print("two_sonar_bot: pressed", time.ticks_diff(pressed_ms, boot_ms), "ms after boot")

state = "forward"
drive(SPEED)
while state != "stopped":
    led.toggle()
    if state == "forward":
        d = front.distance_cm()
        if d is not None and d < FRONT_STOP_CM:
            print("two_sonar_bot: obstacle ahead at", int(d), "cm, reversing")
            state = "reverse"
            drive(-SPEED)
    else:
        d = rear.distance_cm()
        if d is not None and d < REAR_STOP_CM:
            drive(0)
            state = "stopped"
            print("two_sonar_bot: wall behind at", int(d), "cm, stopped")
    time.sleep_ms(LOOP_MS)

time.sleep_ms(500)
print("two_sonar_bot: counts", enc_l.count, enc_r.count)
while True:
    led.toggle()
    time.sleep_ms(500)
