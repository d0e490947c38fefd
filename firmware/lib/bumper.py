# Bumper micro-switch closing to ground, latched by an IRQ so a short press between
# two control steps is not missed.
from machine import Pin


class Bumper:
    def __init__(self, pin):
        self._pin = Pin(pin, Pin.IN, Pin.PULL_UP)
        self.latched = False
        self._pin.irq(self._pressed, Pin.IRQ_FALLING)

    def _pressed(self, pin):
        self.latched = True

    def pressed(self):
        return self._pin.value() == 0

    def clear(self):
        self.latched = self.pressed()
