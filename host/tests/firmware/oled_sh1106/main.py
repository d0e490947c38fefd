# An SH1106 on I2C and one on SPI, driven as the public drivers drive it (sh1106.py here),
# writing text with framebuf's font; the same text drawn into a second FrameBuffer gives the
# pictures' expected pixels.
from machine import I2C, SPI, Pin

import framebuf
import sh1106

i2c = I2C(0, scl=Pin(18), sda=Pin(19))
oled = sh1106.SH1106_I2C(128, 64, i2c)
oled.fill(0)
oled.text("Hello, SH1106!", 0, 0, 1)
oled.text("mpy-fil", 20, 30, 1)
oled.rect(0, 50, 128, 14, 1)
oled.show()

ref = bytearray(128 * 64 // 8)
fb = framebuf.FrameBuffer(ref, 128, 64, framebuf.MONO_VLSB)
fb.text("Hello, SH1106!", 0, 0, 1)
fb.text("mpy-fil", 20, 30, 1)
fb.rect(0, 50, 128, 14, 1)
print("R same", int(ref == oled.buffer))
print("R lit", sum(bin(b).count("1") for b in ref))
print("R ref", list(ref))

spi = SPI(1, baudrate=8_000_000, sck=Pin(14), mosi=Pin(13), miso=Pin(12))
other = sh1106.SH1106_SPI(128, 64, spi, Pin(4), Pin(5), Pin(15))
other.fill(0)
other.text("SPI", 0, 8, 1)
other.vline(127, 0, 64, 1)
other.show()
print("R other", list(other.buffer))
