# The robot spins in place on a TB6612 (tb6612_turn.py) until its IMU's integrated gyro
# says 90 degrees, then stops and settles. The IMU is the one that answers on the bus, driven by its driver
# published on PyPI (unchanged, from build/drivers/) as its README sets it up: an LSM6DSOX
# at 0x6A or an LSM6DSO wired as kits wire it (SA0 high, 0x6B) through micropython-lsm6dsox,
# an MPU-6886 at 0x68 through micropython-mpu6886 (gyro in rad/s, the drivers' default).
import math
import time
from machine import I2C, Pin

from tb6612_turn import drive

i2c = I2C(1, sda=Pin(2), scl=Pin(3))
found = i2c.scan()
if 0x6A in found or 0x6B in found:
    from micropython_lsm6dsox import lsm6dsox

    imu = lsm6dsox.LSM6DSOX(i2c) if 0x6A in found else lsm6dsox.LSM6DSOX(i2c, address=0x6B)
else:
    from mpu6886 import MPU6886

    imu = MPU6886(i2c)

heading_rad = 0.0
last = time.ticks_us()


def integrate():
    global heading_rad, last
    gz = imu.gyro[2]
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
if hasattr(imu, "gyro_range"):
    print("R gyro_range", repr(imu.gyro_range))
    print("R accel_z", imu.acceleration[2])
else:
    print("R whoami", imu.whoami)
    print("R temperature", imu.temperature)
