# The MPU-6886 driver published on PyPI (micropython-mpu6886, unchanged, from build/drivers/)
# set up as its README shows; the robot spins in place on a TB6612 until its integrated
# gyro (rad/s, the driver's default) says 90 degrees, then stops and settles.
import math
import time
from machine import I2C, PWM, Pin

from mpu6886 import MPU6886

i2c = I2C(scl=Pin(22), sda=Pin(21))
sensor = MPU6886(i2c)

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
    gz = sensor.gyro[2]
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
print("R whoami", sensor.whoami)
print("R temperature", sensor.temperature)
