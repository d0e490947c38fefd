# The Pico-Go's LCD drawn with a driver in st7789py's shape (tft.py): landscape (rotation
# 1: MADCTL 0x60, offsets 40, 53), RGB order, a black fill, a red filled rectangle, a
# green outline, text, a blitted 2 x 2 pattern, a corner pixel; then portrait (rotation 0:
# offsets 52, 40) and one pixel at its (0, 0).
import struct
from machine import SPI, Pin

import font8
import tft

spi = SPI(1, baudrate=60_000_000, sck=Pin(10), mosi=Pin(11), miso=None)
lcd = tft.ST7789(
    spi,
    135,
    240,
    reset=Pin(12, Pin.OUT),
    cs=Pin(9, Pin.OUT),
    dc=Pin(8, Pin.OUT),
    backlight=Pin(13, Pin.OUT),
    rotation=1,
    color_order=tft.RGB,
)
print("size", lcd.width, lcd.height)
lcd.fill_rect(20, 30, 50, 20, tft.RED)
lcd.rect(100, 40, 60, 30, tft.GREEN)
lcd.text(font8, "HI", 8, 100, tft.YELLOW, tft.BLUE)
lcd.blit_buffer(struct.pack(">HHHH", tft.RED, tft.GREEN, tft.BLUE, tft.WHITE), 200, 10, 2, 2)
lcd.pixel(239, 134, tft.WHITE)
lcd.rotation(0)
lcd.pixel(0, 0, 0x07FF)
print("done")
