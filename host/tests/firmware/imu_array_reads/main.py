# An LSM6DSOX read as micropython-lib's lsm6dsox driver reads it (written here in its
# manner, not copied): a reset that polls CTRL3_C.SW_RESET, then each vector read into a
# memoryview of one array('h', 3) scratch buffer with readfrom_mem_into, and on SPI with
# readinto; beside it the same registers read as bytes and unpacked little-endian.
import struct
import time
from array import array
from machine import I2C, SPI, Pin

ADDR = 0x6A
CTRL1_XL, CTRL2_G, CTRL3_C, OUTX_L_G, OUTX_L_XL = 0x10, 0x11, 0x12, 0x22, 0x28


class Imu:
    def __init__(self, i2c):
        self.i2c = i2c
        if i2c.readfrom_mem(ADDR, 0x0F, 1)[0] != 108:
            raise OSError("no LSM6DS at 0x%x" % ADDR)
        self.scratch = array("h", [0, 0, 0])
        i2c.writeto_mem(ADDR, CTRL3_C, bytes([i2c.readfrom_mem(ADDR, CTRL3_C, 1)[0] | 0x01]))
        for _ in range(10):
            if not i2c.readfrom_mem(ADDR, CTRL3_C, 1)[0] & 0x01:
                break
            time.sleep_ms(10)
        else:
            raise OSError("the reset never ended")
        i2c.writeto_mem(ADDR, CTRL1_XL, bytes([0x48]))  # 104 Hz, +-4 g
        i2c.writeto_mem(ADDR, CTRL2_G, bytes([0x4C]))  # 104 Hz, 2000 dps
        self.accel_scale = 32768 / 4

    def accel(self):
        mv = memoryview(self.scratch)
        self.i2c.readfrom_mem_into(ADDR, OUTX_L_XL, mv)
        f = self.accel_scale
        return (mv[0] / f, mv[1] / f, mv[2] / f)


imu = Imu(I2C(0, scl=Pin(18), sda=Pin(19)))
time.sleep_ms(20)
print("R accel", imu.accel())
print("R accel_bytes", [v / imu.accel_scale for v in struct.unpack("<3h", imu.i2c.readfrom_mem(ADDR, OUTX_L_XL, 6))])
whole = array("h", [0, 0, 0])
imu.i2c.readfrom_mem_into(ADDR, OUTX_L_XL, whole)  # the array itself
print("R accel_array", list(whole))
imu.i2c.writeto(ADDR, bytes([OUTX_L_XL]), False)
imu.i2c.readfrom_into(ADDR, whole)
print("R accel_readfrom_into", list(whole))

cs = Pin(15, Pin.OUT, value=1)
spi = SPI(1, baudrate=1_000_000, sck=Pin(14), mosi=Pin(13), miso=Pin(12))
cs(0)
spi.write(bytes([CTRL1_XL, 0x48]))
cs(1)
time.sleep_ms(20)
raw = array("h", [0, 0, 0])
cs(0)
spi.write(bytes([0x80 | OUTX_L_XL]))
spi.readinto(memoryview(raw))
cs(1)
print("R spi_accel", [v / 8192 for v in raw])
