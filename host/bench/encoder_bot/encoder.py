# Quadrature encoder counted on every edge of both channels (x4 decoding), as Pico
# motor-control courses write it: an IRQ on A and one on B, each comparing the levels.
from machine import Pin


class QuadEncoder:
    def __init__(self, pin_a, pin_b):
        self.a = Pin(pin_a, Pin.IN, Pin.PULL_UP)
        self.b = Pin(pin_b, Pin.IN, Pin.PULL_UP)
        self.count = 0
        edges = Pin.IRQ_RISING | Pin.IRQ_FALLING
        self.a.irq(trigger=edges, handler=self.on_a)
        self.b.irq(trigger=edges, handler=self.on_b)

    def on_a(self, pin):
        if self.a.value() != self.b.value():
            self.count += 1
        else:
            self.count -= 1

    def on_b(self, pin):
        if self.a.value() == self.b.value():
            self.count += 1
        else:
            self.count -= 1
