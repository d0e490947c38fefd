# The buttons: A on GP20 (to ground, the pin's pull-up), and the board's BOOTSEL button,
# read as rp2 reads it (a short while with the flash's chip select let go).
import rp2
from machine import Pin


class ButtonA:
    def __init__(self):
        self.pin = Pin(20, Pin.IN, Pin.PULL_UP)

    def is_pressed(self):
        return not self.pin.value()


def bootsel_pressed():
    return rp2.bootsel_button() == 1
