# A 240 x 240 ST7789 (Waveshare's Pico-LCD-1.3 pins, SPI1 with polarity 1) driven the way
# russhughes' st7789py drives it, written here: its rotation table for the square panel
# (upside down, rotation 2, MADCTL 0xC0 with the row offset 80; rotation 3, 0xA0 with the
# column offset 80), a window a drawing, colours big-endian, RGB order.
import struct
import time
from machine import SPI, Pin

ROTATIONS = ((0x00, 0, 0), (0x60, 0, 0), (0xC0, 0, 80), (0xA0, 80, 0))  # (MADCTL, xstart, ystart)

spi = SPI(1, baudrate=60_000_000, polarity=1, sck=Pin(10), mosi=Pin(11), miso=None)
cs, dc, rst, bl = Pin(9, Pin.OUT), Pin(8, Pin.OUT), Pin(12, Pin.OUT), Pin(13, Pin.OUT)
xstart = ystart = 0


def write(command=None, data=None):
    cs.off()
    if command is not None:
        dc.off()
        spi.write(command)
    if data is not None:
        dc.on()
        spi.write(data)
        cs.on()


def rotation(n):
    global xstart, ystart
    madctl, xstart, ystart = ROTATIONS[n]
    write(b"\x36", bytes([madctl]))


def fill_rect(x, y, w, h, colour):
    write(b"\x2a", struct.pack(">HH", x + xstart, x + w - 1 + xstart))
    write(b"\x2b", struct.pack(">HH", y + ystart, y + h - 1 + ystart))
    write(b"\x2c")
    one = struct.pack(">H", colour)
    chunks, rest = divmod(w * h, 256)
    for _ in range(chunks):
        write(None, one * 256)
    if rest:
        write(None, one * rest)


rst.on()
time.sleep_ms(10)
rst.off()
time.sleep_ms(10)
rst.on()
time.sleep_ms(120)
for command, data, wait_ms in ((b"\x11", b"\x00", 120), (b"\x3a", b"\x55", 10), (b"\x21", b"\x00", 0)):
    write(command, data)
    time.sleep_ms(wait_ms)
write(b"\x29", b"\x00")
rotation(2)
fill_rect(0, 0, 240, 240, 0x0000)
fill_rect(0, 0, 1, 1, 0xF800)
fill_rect(10, 20, 30, 40, 0x07E0)
rotation(3)
fill_rect(0, 0, 1, 1, 0x001F)
bl.on()
print("done")
