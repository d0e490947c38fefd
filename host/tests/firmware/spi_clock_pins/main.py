# Two APA102 strips on SPI0 sharing MOSI (GP3), each clocked on a pin of its own (GP2, GP6):
# a frame reaches the strips whose clock pin is the SPI's at that instant, as IO_BANK0's
# FUNCSEL says, however it was set: SPI(..., sck=) (the constructor muxes it), Pin.ALT with
# alt=1, a FUNCSEL write through mem32; a plain GPIO output, or the other controller's SPI
# function (SPI1 on GP10), clocks nothing.
from machine import SPI, Pin, mem32

CTRL = 0x40014000 + 4  # GPIOn_CTRL at IO_BANK0 + 8n + 4 (FUNCSEL: bits 4..0)


def frame(rgb):
    return bytes(4) + bytes((0xFF, rgb & 0xFF, rgb >> 8 & 0xFF, rgb >> 16)) + b"\xff" * 4


a, b = Pin(2), Pin(6)
spi = SPI(0, baudrate=1_000_000, sck=a, mosi=Pin(3))  # GP2 muxed to SPI0 by the constructor
b.init(Pin.OUT, value=0)
spi.write(frame(0x000001))  # a only
a.init(Pin.OUT, value=0)
b.init(mode=Pin.ALT, alt=1)
spi.write(frame(0x000002))  # b only
a.init(mode=Pin.ALT, alt=Pin.ALT_SPI)
spi.write(frame(0x000003))  # both
a.init(Pin.OUT, value=0)
b.init(Pin.OUT, value=0)
spi.write(frame(0x000004))  # neither
mem32[CTRL + 8 * 2] = 1  # GP2's FUNCSEL: SPI, through the register
spi.write(frame(0x000005))  # a only
mem32[CTRL + 8 * 2] = 5  # back to SIO (its OE still set: an output again)
b.init(mode=Pin.ALT, alt=Pin.ALT_UART)
spi.write(frame(0x000006))  # neither: GP6 is UART1's now
print("R funcsel", [mem32[CTRL + 8 * n] & 0x1F for n in (2, 6)])
print("R done", 1)
