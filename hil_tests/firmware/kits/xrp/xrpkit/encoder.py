# A wheel encoder, its quadrature decoded by pin interrupts on both edges of A and B: a
# 16-entry table indexed by the previous and the current B/A levels gives the step.
from machine import Pin

# (previous B A) << 2 | (B A now) -> step; B leads going forwards (the way XRPLib's PIO
# decoder counts up, its left count flipped with the motor)
_STEP = (0, -1, 1, 0, 1, 0, 0, -1, -1, 0, 0, 1, 0, 1, -1, 0)


class Encoder:
    """One motor's encoder on pins A and B; counts per wheel turn: RESOLUTION. ``index``
    is the vendor library's PIO state machine; these edges are counted by interrupts."""

    RESOLUTION = 12 * 48.75  # 12 counts per motor turn through a 48.75:1 gearbox

    def __init__(self, index, pin_a, pin_b, flip=False):
        self.a = Pin(pin_a, Pin.IN, Pin.PULL_UP)
        self.b = Pin(pin_b, Pin.IN, Pin.PULL_UP)
        self.sign = -1 if flip else 1
        self.state = self.b.value() << 1 | self.a.value()
        self.count = 0
        self.zero = 0
        edges = Pin.IRQ_RISING | Pin.IRQ_FALLING
        self.a.irq(self._edge, edges)
        self.b.irq(self._edge, edges)

    def _edge(self, _pin):
        now = self.b.value() << 1 | self.a.value()
        self.count += _STEP[self.state << 2 | now]
        self.state = now

    def reset(self):
        self.zero = self.count

    def counts(self):
        return self.sign * (self.count - self.zero)

    def revolutions(self):
        return self.counts() / self.RESOLUTION
