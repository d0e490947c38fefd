# The RGB LEDs: a chain of APA102s on SPI1. A frame is a start frame (32 zero bits), one
# 32-bit frame per LED (0b111 and a 5-bit brightness, then blue, green, red) and an end frame.
from machine import SPI, Pin


class RGBLEDs:
    def __init__(self, count=3):
        self.spi = SPI(1, baudrate=8_000_000, polarity=0, phase=0, sck=Pin(26), mosi=Pin(27))
        self.count = count
        self.data = bytearray(4 + 4 * count + 4)
        for i in range(count):
            self.data[4 + 4 * i] = 0xE0 | 31
        for i in range(4):
            self.data[4 + 4 * count + i] = 0xFF

    def set(self, led, rgb, brightness=31):
        at = 4 + 4 * led
        self.data[at] = 0xE0 | (brightness & 0x1F)
        self.data[at + 1] = rgb[2]
        self.data[at + 2] = rgb[1]
        self.data[at + 3] = rgb[0]

    def show(self):
        self.spi.write(self.data)
