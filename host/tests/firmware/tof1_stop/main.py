# A VL53L1X read through a driver written as the public ones are (vl53l1x.py here), ranging
# one measurement after another: the robot drives at a wall on a TB6612 and stops when the
# range is 0.3 m.
import time
from machine import I2C, PWM, Pin

import vl53l1x

i2c = I2C(0, scl=Pin(22), sda=Pin(21))
t0 = time.ticks_us()
tof = vl53l1x.VL53L1X(i2c)
print("R boot_us", time.ticks_diff(time.ticks_us(), t0))

ain1, ain2, bin1, bin2 = Pin(17, Pin.OUT), Pin(18, Pin.OUT), Pin(23, Pin.OUT), Pin(19, Pin.OUT)
pwm_a, pwm_b = PWM(Pin(16), freq=20_000, duty_u16=0), PWM(Pin(4), freq=20_000, duty_u16=0)


def drive(duty_u16):
    ain1.value(1)
    ain2.value(0)
    bin1.value(1)
    bin2.value(0)
    pwm_a.duty_u16(duty_u16)
    pwm_b.duty_u16(duty_u16)


tof.start()
first = tof.read()
t0 = time.ticks_ms()
n = 1
drive(40_000)
mm = first
while mm is None or mm > 300:
    mm = tof.read()
    n += 1
drive(0)
tof.stop()
print("R first_mm", first)
print("R stop_mm", mm)
print("R period_ms", time.ticks_diff(time.ticks_ms(), t0) / (n - 1))
