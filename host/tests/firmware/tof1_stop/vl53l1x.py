# A VL53L1X driver written as the public MicroPython ones are (16-bit register addresses
# through readfrom_mem/writeto_mem's addrsize=16): check the model id, wait for the boot
# state, send a configuration block at 0x002D, start ranging, and for each range wait for
# the interrupt status at its polarity, read the range, clear the interrupt.
import time
from micropython import const

_SOFT_RESET = const(0x0000)
_GPIO_HV_MUX_CTRL = const(0x0030)
_GPIO_TIO_HV_STATUS = const(0x0031)
_INTERRUPT_CLEAR = const(0x0086)
_MODE_START = const(0x0087)
_RANGE_STATUS = const(0x0089)
_RANGE_MM = const(0x0096)
_SYSTEM_STATUS = const(0x00E5)
_MODEL_ID = const(0x010F)


class VL53L1X:
    def __init__(self, i2c, address=0x29):
        self.i2c = i2c
        self.address = address
        model = self._read(_MODEL_ID, 2)
        if model != b"\xea\xcc":
            raise RuntimeError("not a VL53L1X: model id %r" % model)
        self._write(_SOFT_RESET, 0x00)
        time.sleep_ms(1)
        self._write(_SOFT_RESET, 0x01)
        while not self._read(_SYSTEM_STATUS, 1)[0] & 0x01:
            time.sleep_ms(1)
        config = bytearray(91)  # 0x002D..0x0087: the pads, the interrupt (active high), the timing
        config[0x0030 - 0x002D] = 0x01
        config[0x0031 - 0x002D] = 0x02
        self.i2c.writeto_mem(self.address, 0x002D, config, addrsize=16)

    def _read(self, reg, n):
        return self.i2c.readfrom_mem(self.address, reg, n, addrsize=16)

    def _write(self, reg, value):
        self.i2c.writeto_mem(self.address, reg, bytes((value,)), addrsize=16)

    def start(self):
        self._write(_MODE_START, 0x40)

    def stop(self):
        self._write(_MODE_START, 0x00)

    def data_ready(self):
        polarity = not (self._read(_GPIO_HV_MUX_CTRL, 1)[0] & 0x10)
        return (self._read(_GPIO_TIO_HV_STATUS, 1)[0] & 0x01) == polarity

    def read(self):
        while not self.data_ready():
            time.sleep_ms(1)
        status = self._read(_RANGE_STATUS, 1)[0] & 0x1F
        mm = int.from_bytes(self._read(_RANGE_MM, 2), "big")
        self._write(_INTERRUPT_CLEAR, 0x01)
        return mm if status == 9 else None
