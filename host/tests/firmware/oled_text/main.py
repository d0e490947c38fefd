# The published micropython-ssd1306 driver, set up as its README shows, writing text with
# framebuf's font; the same text drawn into a second FrameBuffer gives the picture's
# expected pixels (the hash of the driver's buffer, and its lit pixel count).
from machine import I2C, SPI, Pin

import framebuf
import ssd1306

i2c = I2C(0, scl=Pin(18), sda=Pin(19))
oled = ssd1306.SSD1306_I2C(128, 64, i2c)
oled.fill(0)
oled.text("Hello, OLED!", 0, 0, 1)
oled.text("mpy-fil", 20, 30, 1)
oled.show()

ref = bytearray(128 * 64 // 8)
fb = framebuf.FrameBuffer(ref, 128, 64, framebuf.MONO_VLSB)
fb.text("Hello, OLED!", 0, 0, 1)
fb.text("mpy-fil", 20, 30, 1)
print("R same", int(ref == oled.buffer))
print("R lit", sum(bin(b).count("1") for b in ref))
print("R ref", list(ref))

spi = SPI(1, baudrate=8_000_000, sck=Pin(14), mosi=Pin(13), miso=Pin(12))
small = ssd1306.SSD1306_SPI(128, 32, spi, Pin(4), Pin(5), Pin(15))
small.fill(0)
small.text("SPI 32", 0, 8, 1)
small.show()
print("R small", list(small.buffer))
