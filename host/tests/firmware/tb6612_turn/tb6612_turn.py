# The bench robot's TB6612 as the spin and compass firmwares drive it (a module of theirs on
# the board's path): channel A (PWM GPIO16, AIN1 17, AIN2 18) the left wheel, B (PWM 21,
# BIN1 22, BIN2 23) the right; drive(duty) turns the robot left in place, drive(0) stops it;
# turn_then_stop() turns for a second and lets it settle for another.
import time
from machine import PWM, Pin

ain1, ain2, bin1, bin2 = Pin(17, Pin.OUT), Pin(18, Pin.OUT), Pin(22, Pin.OUT), Pin(23, Pin.OUT)
pwm_a, pwm_b = PWM(Pin(16), freq=20_000, duty_u16=0), PWM(Pin(21), freq=20_000, duty_u16=0)


def drive(duty_u16):
    ain1.value(0)  # left wheel backwards, right forwards: a left turn in place
    ain2.value(1)
    bin1.value(1)
    bin2.value(0)
    pwm_a.duty_u16(duty_u16)
    pwm_b.duty_u16(duty_u16)


def turn_then_stop(duty_u16=30_000, turn_ms=1000, settle_ms=1000):
    drive(duty_u16)
    time.sleep_ms(turn_ms)
    drive(0)
    time.sleep_ms(settle_ms)
