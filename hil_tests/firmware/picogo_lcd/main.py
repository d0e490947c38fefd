# The Pico-Go's 1.14" LCD driven the way Waveshare's demo (ST7789.py) drives it, written
# here, not copied: a framebuf.RGB565 subclass of 240 x 135 drawn in RAM, each command
# and parameter its own transfer with chip select raised between, MADCTL 0x70, COLMOD
# 0x05, INVON, and show() sending the whole buffer (64,800 bytes) in one spi.write to
# the window columns 40-279, rows 53-187. framebuf keeps an RGB565 pixel as a native
# uint16 (extmod/modframebuf.c, rgb565_setpixel: little-endian on the RP2040), so the
# demo's colour names are the panel's colours with their bytes swapped.
import time
from machine import SPI, Pin

import framebuf

BLUE = 0xFF00  # (the demo's names: 0x00FF on the glass, and so on)
ORANGE = 0x07FF
WHITE = 0xFFFF


class Lcd(framebuf.FrameBuffer):
    def __init__(self):
        self.width, self.height = 240, 135
        self.rst = Pin(12, Pin.OUT)
        self.bl = Pin(13, Pin.OUT)
        self.bl(1)
        self.cs = Pin(9, Pin.OUT)
        self.cs(1)
        self.spi = SPI(1, 10_000_000, polarity=0, phase=0, sck=Pin(10), mosi=Pin(11), miso=None)
        self.dc = Pin(8, Pin.OUT)
        self.dc(1)
        self.buffer = bytearray(self.width * self.height * 2)
        super().__init__(self.buffer, self.width, self.height, framebuf.RGB565)
        self.setup()

    def send(self, dc, byte):
        self.cs(1)
        self.dc(dc)
        self.cs(0)
        self.spi.write(bytearray([byte]))
        self.cs(1)

    def setup(self):
        self.rst(1)
        self.rst(0)
        self.rst(1)
        for command, params in ((0x36, (0x70,)), (0x3A, (0x05,)), (0xB2, (0x0C, 0x0C, 0x00, 0x33, 0x33))):
            self.send(0, command)
            for p in params:
                self.send(1, p)
        for command in (0x21, 0x11, 0x29):
            self.send(0, command)

    def show(self):
        for command, params in ((0x2A, (0x00, 0x28, 0x01, 0x17)), (0x2B, (0x00, 0x35, 0x00, 0xBB))):
            self.send(0, command)
            for p in params:
                self.send(1, p)
        self.send(0, 0x2C)
        self.cs(1)
        self.dc(1)
        self.cs(0)
        self.spi.write(self.buffer)
        self.cs(1)


lcd = Lcd()
lcd.fill(BLUE)
lcd.fill_rect(145, 50, 65, 40, ORANGE)
lcd.text("PicoGo", 10, 5, WHITE)
t0 = time.ticks_us()
lcd.show()
print("shown", time.ticks_diff(time.ticks_us(), t0))
for y in range(5, 13):  # where the text is white, a bit a pixel, 240 of them, as hex
    mask = 0
    for x in range(240):
        mask = mask << 1 | (lcd.pixel(x, y) == WHITE)
    print("text", y, "%060x" % mask)
print("done")
