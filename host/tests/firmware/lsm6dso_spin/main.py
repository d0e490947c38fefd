# The LSM6DSOX driver published on PyPI (micropython-lsm6dsox, unchanged, from build/drivers/)
# driving an LSM6DSO (same WHO_AM_I and registers) wired as kits wire it, SA0 high at 0x6B; the robot spins
# in place on a TB6612 until its integrated gyro says 90 degrees, then stops and settles.
import math
import time
from machine import I2C, PWM, Pin

from micropython_lsm6dsox import lsm6dsox

i2c = I2C(1, sda=Pin(2), scl=Pin(3))
lsm = lsm6dsox.LSM6DSOX(i2c, address=0x6B)

ain1, ain2, bin1, bin2 = Pin(17, Pin.OUT), Pin(18, Pin.OUT), Pin(22, Pin.OUT), Pin(23, Pin.OUT)
pwm_a, pwm_b = PWM(Pin(16), freq=20_000, duty_u16=0), PWM(Pin(21), freq=20_000, duty_u16=0)


def drive(duty_u16):
    ain1.value(0)  # left wheel backwards, right forwards: a left turn in place
    ain2.value(1)
    bin1.value(1)
    bin2.value(0)
    pwm_a.duty_u16(duty_u16)
    pwm_b.duty_u16(duty_u16)


heading_rad = 0.0
last = time.ticks_us()


def integrate():
    global heading_rad, last
    gz = lsm.gyro[2]
    now = time.ticks_us()
    heading_rad += gz * time.ticks_diff(now, last) * 1e-6
    last = now


for _ in range(20):  # still: the gyro reads its bias only
    integrate()
    time.sleep_ms(5)
drive(30_000)
while heading_rad < math.radians(90):
    integrate()
    time.sleep_ms(5)
drive(0)
for _ in range(100):  # stopped: the turn settles (the wheels' lag), still integrated
    integrate()
    time.sleep_ms(5)
print("R heading_deg", math.degrees(heading_rad))
print("R accel_z", lsm.acceleration[2])
