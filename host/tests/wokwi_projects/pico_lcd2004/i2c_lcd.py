# The PCF8574 I2C backpack under lcd_api.LcdApi, in the shape of the common i2c_lcd.py:
# P0 RS, P1 RW, P2 E, P3 the backlight, P4..P7 D4..D7; the controller in 4-bit mode, a
# byte as two nibbles, each latched by a high then low E. Written for these tests.
import time

from lcd_api import LcdApi

MASK_RS = 0x01
MASK_RW = 0x02
MASK_E = 0x04
SHIFT_BACKLIGHT = 3
SHIFT_DATA = 4


class I2cLcd(LcdApi):
    def __init__(self, i2c, i2c_addr, num_lines, num_columns):
        self.i2c = i2c
        self.i2c_addr = i2c_addr
        self.i2c.writeto(self.i2c_addr, bytes([0]))
        time.sleep_ms(20)  # the LCD's power-on time
        for _ in range(3):  # three 8-bit function resets, whatever mode it is in
            self.hal_write_init_nibble(self.FUNCTION_RESET)
            time.sleep_ms(5)
        self.hal_write_init_nibble(self.FUNCTION)  # 4-bit from now on
        time.sleep_ms(1)
        LcdApi.__init__(self, num_lines, num_columns)
        cmd = self.FUNCTION
        if num_lines > 1:
            cmd |= self.FUNCTION_2LINES
        self.hal_write_command(cmd)

    def hal_write_init_nibble(self, nibble):
        byte = ((nibble >> 4) & 0x0F) << SHIFT_DATA
        self.i2c.writeto(self.i2c_addr, bytes([byte | MASK_E]))
        self.i2c.writeto(self.i2c_addr, bytes([byte]))

    def hal_backlight_on(self):
        self.i2c.writeto(self.i2c_addr, bytes([1 << SHIFT_BACKLIGHT]))

    def hal_backlight_off(self):
        self.i2c.writeto(self.i2c_addr, bytes([0]))

    def _write(self, value, rs):
        light = self.backlight << SHIFT_BACKLIGHT
        for nibble in (value >> 4, value & 0x0F):
            byte = rs | light | (nibble & 0x0F) << SHIFT_DATA
            self.i2c.writeto(self.i2c_addr, bytes([byte | MASK_E]))
            self.i2c.writeto(self.i2c_addr, bytes([byte]))

    def hal_write_command(self, cmd):
        self._write(cmd, 0)
        if cmd <= 3:
            time.sleep_ms(5)  # clear and home take 1.52 ms

    def hal_write_data(self, data):
        self._write(data, MASK_RS)
