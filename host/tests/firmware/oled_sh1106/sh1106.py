# An SH1106 driver written as the public MicroPython ones are (a FrameBuffer subclass; the
# controller has no horizontal addressing mode, so show() sends each page in turn, at the
# glass's column offset of 2, over I2C or over SPI with D/C and CS).
from micropython import const

import framebuf

_PAGE = const(0xB0)
_COL_LO = const(0x00)
_COL_HI = const(0x10)


class SH1106(framebuf.FrameBuffer):
    def __init__(self, width, height, col_offset=2):
        self.width = width
        self.height = height
        self.pages = height // 8
        self.col_offset = col_offset
        self.buffer = bytearray(self.pages * width)
        super().__init__(self.buffer, width, height, framebuf.MONO_VLSB)
        self.init_display()

    def init_display(self):
        for cmd in (
            0xAE,  # display off
            0xD5,
            0x80,  # clock
            0xA8,
            self.height - 1,  # multiplex
            0xD3,
            0x00,  # offset
            0x40,  # start line 0
            0xAD,
            0x8B,  # DC-DC on
            0xA1,  # segment remap
            0xC8,  # COM scan from the top
            0xDA,
            0x12,  # COM pins
            0x81,
            0x80,  # contrast
            0xD9,
            0x22,  # pre-charge
            0xDB,
            0x35,  # VCOM
            0x32,  # pump voltage
            0xA4,  # from RAM
            0xA6,  # not inverted
        ):
            self.write_cmd(cmd)
        self.fill(0)
        self.show()
        self.poweron()

    def poweron(self):
        self.write_cmd(0xAF)

    def poweroff(self):
        self.write_cmd(0xAE)

    def show(self):
        col = self.col_offset
        for page in range(self.pages):
            self.write_cmd(_PAGE | page)
            self.write_cmd(_COL_LO | (col & 0x0F))
            self.write_cmd(_COL_HI | (col >> 4))
            self.write_data(self.buffer[page * self.width : (page + 1) * self.width])


class SH1106_I2C(SH1106):
    def __init__(self, width, height, i2c, addr=0x3C):
        self.i2c = i2c
        self.addr = addr
        super().__init__(width, height)

    def write_cmd(self, cmd):
        self.i2c.writeto(self.addr, bytes((0x80, cmd)))

    def write_data(self, buf):
        self.i2c.writevto(self.addr, (b"\x40", buf))


class SH1106_SPI(SH1106):
    def __init__(self, width, height, spi, dc, res, cs):
        self.spi = spi
        self.dc = dc
        self.res = res
        self.cs = cs
        dc.init(dc.OUT, value=0)
        res.init(res.OUT, value=1)
        cs.init(cs.OUT, value=1)
        res(0)
        res(1)
        super().__init__(width, height)

    def write_cmd(self, cmd):
        self.dc(0)
        self.cs(0)
        self.spi.write(bytes((cmd,)))
        self.cs(1)

    def write_data(self, buf):
        self.dc(1)
        self.cs(0)
        self.spi.write(buf)
        self.cs(1)
