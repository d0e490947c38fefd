# The display: the SH1106 on SPI0, sharing MOSI (GP3) with the RGB LEDs. Its clock pin (GP2)
# is SPI0's only while the display is written to (Pin.ALT, alt=1: GPIO_FUNC_SPI), a low
# GPIO output between writes, as kits do when the bus's pins are shared with other parts:
# each command alone hands the clock to the SPI and takes it back; show() hands it over
# once for all its pages (a command written through write_cmd inside it would take it back
# before the page's data).
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
        mv = memoryview(self.buffer)
        for page in range(8):
            sh1106.SH1106_SPI.write_cmd(self, bytes((0xB0 | page, 0x02, 0x10)))  # page, column 2
            self.write_data(mv[page * 128 : page * 128 + 128])
        self.sck.init(mode=Pin.OUT, value=0)
