# The RGB LEDs: a chain of APA102s on SPI0, sharing MOSI (GP3) with the display and clocked
# on a pin of their own (GP6): the SPI's clock is on GP6 only while a frame goes out (Pin.ALT,
# alt=1: GPIO_FUNC_SPI), a low GPIO output between frames, so the display's transfers never
# clock the LEDs, nor theirs the display. A frame is a start frame (32 zero bits), one 32-bit
# frame per LED (0b111 and a 5-bit brightness, then blue, green, red) and an end frame.
from machine import SPI, Pin


class RGBLEDs:
    def __init__(self, count=3):
        self.sck = Pin(6)
        # SPI0 again, at the LEDs' clock rate; its MISO is given GP0 (the display's D/C),
        # which is made a GPIO output again at once
        self.spi = SPI(id=0, baudrate=8_000_000, polarity=0, phase=0, sck=self.sck, mosi=Pin(3), miso=Pin(0))
        Pin(0).init(Pin.OUT, value=0)
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
        self.sck.init(mode=Pin.ALT, alt=1)
        self.spi.write(self.data)
        self.sck.value(0)
        self.sck.init(mode=Pin.OUT)
