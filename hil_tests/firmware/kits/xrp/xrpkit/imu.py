# The controller's LSM6DSO (accelerometer and gyro) on I2C1 at 0x6B: the gyro's z rate,
# integrated in degrees by whoever calls update() often.
import time
from array import array
from machine import I2C, Pin

_ADDRESS = 0x6B
_CTRL2_G = 0x11
_CTRL3_C = 0x12
_OUTZ_L_G = 0x26
_MDPS_PER_LSB = 70.0  # at +-2000 dps (datasheet table 2)


class IMU:
    def __init__(self, scl="I2C_SCL_1", sda="I2C_SDA_1"):
        self.i2c = I2C(1, scl=Pin(scl), sda=Pin(sda), freq=400_000)
        self.i2c.writeto_mem(_ADDRESS, _CTRL3_C, b"\x44")  # BDU, auto-increment
        self.i2c.writeto_mem(_ADDRESS, _CTRL2_G, b"\x5c")  # 208 Hz, +-2000 dps
        self.z = array("h", [0])
        self.heading = 0.0
        self.t = time.ticks_us()

    def rate_z(self):
        self.i2c.readfrom_mem_into(_ADDRESS, _OUTZ_L_G, self.z)
        return self.z[0] * _MDPS_PER_LSB / 1000

    def update(self):
        now = time.ticks_us()
        self.heading += self.rate_z() * time.ticks_diff(now, self.t) / 1e6
        self.t = now
        return self.heading

    def reset_heading(self):
        self.heading = 0.0
        self.t = time.ticks_us()
