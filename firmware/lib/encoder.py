# Quadrature wheel encoder counted in software: an IRQ on both edges of channel A,
# channel B read for direction (2 counts per A cycle).
from machine import Pin


class QuadratureEncoder:
    def __init__(self, pin_a, pin_b, invert=False):
        self._a = Pin(pin_a, Pin.IN)
        self._b = Pin(pin_b, Pin.IN)
        self._step = -1 if invert else 1
        self.count = 0
        self._a.irq(self._edge, Pin.IRQ_RISING | Pin.IRQ_FALLING)

    def _edge(self, pin):
        # A leads B going forward: right after an A edge, A != B
        if pin.value() != self._b.value():
            self.count += self._step
        else:
            self.count -= self._step

    def take(self):
        """Counts since the last call."""
        n = self.count
        self.count = 0
        return n
