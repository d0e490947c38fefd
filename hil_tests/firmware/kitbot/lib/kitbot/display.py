# The display: the SH1106 on SPI0. Its clock pin is SPI0's only while a transfer runs
# (Pin.ALT, alt=1: GPIO_FUNC_SPI) and a low GPIO output between them, as kits do when the
# bus's pins are shared with other parts.
from machine import SPI, Pin

from . import sh1106


class Display(sh1106.SH1106_SPI):
    def __init__(self):
        self.sck = Pin(2)
        self.sck.init(mode=Pin.OUT, value=0)
        spi = SPI(id=0, baudrate=4_000_000, polarity=0, phase=0, sck=self.sck, mosi=Pin(3), miso=None)
        super().__init__(spi, Pin(0), Pin(1))
        self.sck.init(mode=Pin.OUT, value=0)
        self.reset()

    def write_cmd(self, cmd):
        self.sck.init(mode=Pin.ALT, alt=1)
        super().write_cmd(cmd)
        self.sck.init(mode=Pin.OUT, value=0)

    def show(self):
        self.sck.init(mode=Pin.ALT, alt=1)
        super().show()
        self.sck.init(mode=Pin.OUT, value=0)
