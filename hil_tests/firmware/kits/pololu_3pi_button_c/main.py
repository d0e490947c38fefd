# The 3pi+ 2040's button C is on GP0, the display's DC line: the kit's library reads it
# between display writes by making the pin an input with its pull-up for a moment, then
# driving it low again (buttons.py's ButtonC: a new Pin(0) for the drive). Written in that
# library's style (not copied), with the kitbot package's display on SPI0 (DC on GP0): a
# screen shown, then the button read, every 50 ms; each screen's frame buffer goes to the
# console in hex (the test holds the display's picture to it: the DC the pin drives reaches
# the display through the button's line).
import time
from binascii import hexlify
from machine import Pin

from kitbot.display import Display


class ButtonC:
    def __init__(self):
        self.pin = Pin(0)

    def is_pressed(self):
        self.pin.init(Pin.IN, Pin.PULL_UP)
        ret = self.pin.value()
        Pin(0).init(Pin.OUT, value=0)  # (kept low by default, as the library does)
        return not ret


T0 = time.ticks_ms()
display = Display()
button = ButtonC()
for step in range(8):
    display.fill(0)
    display.text("step %d" % step, 0, 0)
    display.fill_rect(4 + 12 * step, 32, 8, 8, 1)
    display.show()
    print(
        "C step", step, time.ticks_diff(time.ticks_ms(), T0), int(button.is_pressed()), hexlify(display.buffer).decode()
    )
    time.sleep_ms(50)
print("done")
