# A VL53L0X in back-to-back ranging, read the way its drivers read it: RESULT_INTERRUPT_STATUS
# polled for a new measurement, the range at RESULT_RANGE_STATUS + 10, the interrupt cleared.
SYSRANGE_START = 0x00
SYSTEM_INTERRUPT_CLEAR = 0x0B
RESULT_INTERRUPT_STATUS = 0x13
RESULT_RANGE_MM = 0x14 + 10
IDENTIFICATION_MODEL_ID = 0xC0


class VL53L0X:
    def __init__(self, i2c, address=0x29):
        self.i2c, self.address = i2c, address
        if i2c.readfrom_mem(address, IDENTIFICATION_MODEL_ID, 1)[0] != 0xEE:
            raise OSError("VL53L0X not found at 0x%02x" % address)
        self.buf = bytearray(2)
        self.status = bytearray(1)
        i2c.writeto_mem(address, SYSRANGE_START, b"\x02")  # back-to-back

    def ready(self):
        self.i2c.readfrom_mem_into(self.address, RESULT_INTERRUPT_STATUS, self.status)
        return self.status[0] & 0x07 != 0

    def read_mm(self):
        self.i2c.readfrom_mem_into(self.address, RESULT_RANGE_MM, self.buf)
        self.i2c.writeto_mem(self.address, SYSTEM_INTERRUPT_CLEAR, b"\x01")
        return self.buf[0] << 8 | self.buf[1]
