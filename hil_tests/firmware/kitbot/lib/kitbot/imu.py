# The IMU: an LSM6DSO (accelerometer and gyro, 0x6B) and an LIS3MDL (compass, 0x1E) on I2C0.
# Each chip is reset as its datasheet says (set the self-clearing bit, poll until the chip
# clears it); the vectors are read straight into array('h', 3) buffers.
from array import array
from machine import I2C, Pin
from micropython import const

_LSM6DSO = const(0x6B)
_LIS3MDL = const(0x1E)
_CTRL1_XL = const(0x10)
_CTRL2_G = const(0x11)
_CTRL3_C = const(0x12)
_OUTX_L_G = const(0x22)
_OUTX_L_A = const(0x28)
_CTRL_REG1 = const(0x20)
_CTRL_REG2 = const(0x21)
_CTRL_REG3 = const(0x22)
_OUT_X_L = const(0x28)


class _Chip:
    def __init__(self, i2c, address):
        self.i2c = i2c
        self.address = address
        self.byte = bytearray(1)

    def read_reg(self, reg):
        self.i2c.readfrom_mem_into(self.address, reg, self.byte)
        return self.byte[0]

    def write_reg(self, reg, value):
        self.byte[0] = value
        self.i2c.writeto_mem(self.address, reg, self.byte)

    def wait_clear(self, reg, bit):
        self.write_reg(reg, self.read_reg(reg) | bit)
        polls = 0
        while self.read_reg(reg) & bit:
            polls += 1
        return polls


class Vector:
    def __init__(self, chip, reg):
        self.chip = chip
        self.reg = reg
        self.last = array("h", [0, 0, 0])

    def read(self):
        self.chip.i2c.readfrom_mem_into(self.chip.address, self.reg, self.last)
        return self.last


class IMU:
    def __init__(self):
        i2c = I2C(id=0, scl=Pin(5), sda=Pin(4), freq=400_000)
        for _ in range(10):  # clock the bus free of a chip stuck mid-byte
            try:
                i2c.writeto(0, "")
            except OSError:
                pass
        self.i2c = i2c
        self.lsm = _Chip(i2c, _LSM6DSO)
        self.lis = _Chip(i2c, _LIS3MDL)
        self.gyro = Vector(self.lsm, _OUTX_L_G)
        self.acc = Vector(self.lsm, _OUTX_L_A)
        self.mag = Vector(self.lis, _OUT_X_L)

    def detect(self):
        return self.lsm.read_reg(0x0F) == 0x6C and self.lis.read_reg(0x0F) == 0x3D

    def reset(self):
        # CTRL3_C: BOOT (0x80) then SW_RESET (0x01); CTRL_REG2: REBOOT (0x08) then SOFT_RST (0x04)
        return [
            self.lsm.wait_clear(_CTRL3_C, 0x80),
            self.lsm.wait_clear(_CTRL3_C, 0x01),
            self.lis.wait_clear(_CTRL_REG2, 0x08),
            self.lis.wait_clear(_CTRL_REG2, 0x04),
        ]

    def enable_default(self):
        self.lsm.write_reg(_CTRL1_XL, 0x80)  # 1.66 kHz, +-2 g
        self.lsm.write_reg(_CTRL2_G, 0x8C)  # 1.66 kHz, 2000 dps
        self.lsm.write_reg(_CTRL3_C, 0x44)  # BDU, IF_INC
        self.lis.write_reg(_CTRL_REG1, 0x70)  # ultra-high performance X/Y, 10 Hz
        self.lis.write_reg(_CTRL_REG2, 0x00)  # +-4 gauss
        self.lis.write_reg(_CTRL_REG3, 0x00)  # continuous conversion
