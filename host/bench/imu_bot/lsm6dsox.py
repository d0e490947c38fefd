# An LSM6DSOX on I2C as its public MicroPython drivers read it: the identity checked, a
# software reset, both sensors at one output data rate with block data update and register
# auto-increment, STATUS_REG polled for data-ready, then the gyro and accelerometer in one
# 12-byte read from OUTX_L_G into a buffer allocated once.
import struct

WHO_AM_I = 0x0F
CTRL1_XL = 0x10
CTRL2_G = 0x11
CTRL3_C = 0x12
STATUS_REG = 0x1E
OUTX_L_G = 0x22
GYRO_DPS = {0: 0.00875, 1: 0.0175, 2: 0.035, 3: 0.07}  # per count at 250, 500, 1000, 2000 dps
ACCEL_G = {0: 0.000061, 1: 0.000488, 2: 0.000122, 3: 0.000244}  # per count at 2, 16, 4, 8 g


class LSM6DSOX:
    def __init__(self, i2c, address=0x6A, odr=0x5, gyro_fs=3, accel_fs=0):
        self.i2c, self.address = i2c, address
        self.buf = bytearray(12)
        self.one = bytearray(1)
        if self._reg(WHO_AM_I) != 0x6C:
            raise OSError("LSM6DSOX not found at 0x%02x" % address)
        self._write(CTRL3_C, 0x01)  # SW_RESET
        while self._reg(CTRL3_C) & 0x01:
            pass
        self._write(CTRL3_C, 0x44)  # BDU, IF_INC
        self._write(CTRL1_XL, odr << 4 | accel_fs << 2)
        self._write(CTRL2_G, odr << 4 | gyro_fs << 2)
        self.gyro_scale, self.accel_scale = GYRO_DPS[gyro_fs], ACCEL_G[accel_fs]

    def _reg(self, reg):
        self.i2c.readfrom_mem_into(self.address, reg, self.one)
        return self.one[0]

    def _write(self, reg, value):
        self.one[0] = value
        self.i2c.writeto_mem(self.address, reg, self.one)

    def data_ready(self):
        return self._reg(STATUS_REG) & 0x03 == 0x03  # XLDA and GDA

    def read_raw(self):
        """The six counts (gyro x, y, z, accel x, y, z) of the newest sample."""
        self.i2c.readfrom_mem_into(self.address, OUTX_L_G, self.buf)
        return struct.unpack("<6h", self.buf)
