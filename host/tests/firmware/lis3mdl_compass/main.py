# The LIS3MDL driver published on PyPI (micropython-lis3mdl, unchanged, from build/drivers/)
# set up as its quickstart shows. The robot spins in place on a TB6612 (tb6612_turn.py)
# for a turn and a half, keeping each axis' least and greatest reading (the hard-iron
# calibration: the offset is their middle), stops, and prints its compass heading with and
# without it.
import math
import time
from machine import I2C, Pin

from micropython_lis3mdl import lis3mdl

from tb6612_turn import drive

i2c = I2C(1, sda=Pin(2), scl=Pin(3))
lis = lis3mdl.LIS3MDL(i2c)

low = [1e9, 1e9]
high = [-1e9, -1e9]
drive(30_000)
t0 = time.ticks_ms()
while time.ticks_diff(time.ticks_ms(), t0) < 6000:
    magx, magy, magz = lis.magnetic
    for i, v in enumerate((magx, magy)):
        low[i] = min(low[i], v)
        high[i] = max(high[i], v)
    time.sleep_ms(100)
drive(0)
time.sleep_ms(1000)
offset = [(low[i] + high[i]) / 2 for i in range(2)]
sx = sy = 0.0
for _ in range(5):
    magx, magy, magz = lis.magnetic
    sx += magx
    sy += magy
    time.sleep_ms(100)
sx /= 5
sy /= 5
print("R offset_ut", offset)
print("R radius_ut", [(high[i] - low[i]) / 2 for i in range(2)])
print("R raw_deg", math.degrees(math.atan2(sy, sx)) % 360)
print("R heading_deg", math.degrees(math.atan2(sy - offset[1], sx - offset[0])) % 360)
print("R z_ut", magz)
