# An SH1106 128 x 64 OLED on SPI: a framebuf.FrameBuffer whose show() sends each page at the
# glass's column offset of 2 (the controller has no horizontal addressing mode).
import time
from machine import Pin
from micropython import const

import framebuf

_PAGE = const(0xB0)
_COL_LO = const(0x00)
_COL_HI = const(0x10)
_INIT = (0xAE, 0xD5, 0x80, 0xA8, 0x3F, 0xD3, 0x00, 0x40, 0xAD, 0x8B, 0xA1, 0xC8, 0xDA, 0x12, 0x81, 0x80, 0xA4, 0xA6)


class SH1106_SPI(framebuf.FrameBuffer):
    def __init__(self, spi, dc, res):
        self.spi = spi
        self.dc = dc
        self.res = res
        self.buffer = bytearray(128 * 8)
        super().__init__(self.buffer, 128, 64, framebuf.MONO_VLSB)
        dc.init(Pin.OUT, value=0)
        res.init(Pin.OUT, value=1)

    def reset(self):
        self.res(0)
        time.sleep_ms(1)
        self.res(1)
        time.sleep_ms(1)
        self.write_cmd(bytes(_INIT))
        self.fill(0)
        self.show()
        self.write_cmd(b"\xaf")

    def write_cmd(self, cmd):
        self.dc(0)
        self.spi.write(cmd)

    def write_data(self, buf):
        self.dc(1)
        self.spi.write(buf)

    def show(self):
        mv = memoryview(self.buffer)
        for page in range(8):
            self.write_cmd(bytes((_PAGE | page, _COL_LO | 2, _COL_HI)))
            self.write_data(mv[page * 128 : page * 128 + 128])
