# The QMC5883L driver published on PyPI (micropython-qmc5883l, unchanged, from build/drivers/)
# set up as its docstring shows. The robot turns in place on a TB6612 (tb6612_turn.py) for a
# second, stops, and prints its compass heading (atan2 of y and x, ten readings averaged),
# twice.
import math
import time
from machine import I2C, Pin

from micropython_qmc5883l import qmc5883l

from tb6612_turn import turn_then_stop

i2c = I2C(1, sda=Pin(2), scl=Pin(3))
qmc = qmc5883l.QMC5883L(i2c)


def heading():
    sx = sy = 0.0
    for _ in range(10):
        mag_x, mag_y, mag_z = qmc.magnetic
        sx += mag_x
        sy += mag_y
    return math.degrees(math.atan2(sy, sx)) % 360, mag_z


for name in ("first", "second"):
    turn_then_stop()
    t0 = time.ticks_ms()
    deg, z_gauss = heading()
    print("R", name + "_deg", deg)
    print("R", name + "_ms", time.ticks_diff(time.ticks_ms(), t0))
    print("R z_gauss", z_gauss)
    print("R done", repr(name))
