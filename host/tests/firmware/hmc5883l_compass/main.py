# An HMC5883L compass read as the public MicroPython drivers read it (none is published on
# PyPI): the identification registers checked ('H43'), 8-sample averaging at 15 Hz, gain
# 1090 LSB/gauss, continuous mode; the six data registers read from 0x03 in one transfer,
# X, Z, Y, big-endian. The robot turns in place on a TB6612 (tb6612_turn.py) for a second,
# stops, and prints its heading (atan2 of y and x, ten samples averaged), twice.
import math
import struct
import time
from machine import I2C, Pin

from tb6612_turn import turn_then_stop

ADDRESS = 0x1E
i2c = I2C(1, sda=Pin(2), scl=Pin(3))
ident = i2c.readfrom_mem(ADDRESS, 0x0A, 3)
if ident != b"H43":
    raise OSError("no HMC5883L: identification %r" % ident)
i2c.writeto_mem(ADDRESS, 0x00, b"\x70")  # configuration A: 8 samples averaged, 15 Hz
i2c.writeto_mem(ADDRESS, 0x01, b"\x20")  # configuration B: gain 1090 LSB/gauss
i2c.writeto_mem(ADDRESS, 0x02, b"\x00")  # mode: continuous
time.sleep_ms(100)


def read_gauss():
    while not i2c.readfrom_mem(ADDRESS, 0x09, 1)[0] & 0x01:  # status: RDY
        time.sleep_ms(1)
    x, z, y = struct.unpack(">hhh", i2c.readfrom_mem(ADDRESS, 0x03, 6))
    return x / 1090, y / 1090, z / 1090


def heading():
    sx = sy = 0.0
    for _ in range(10):
        x, y, z = read_gauss()
        sx += x
        sy += y
        time.sleep_ms(67)  # the next sample (15 Hz)
    return math.degrees(math.atan2(sy, sx)) % 360, z


for name in ("first", "second"):
    turn_then_stop()
    deg, z_gauss = heading()
    print("R", name + "_deg", deg)
    print("R z_gauss", z_gauss)
    print("R done", repr(name))
