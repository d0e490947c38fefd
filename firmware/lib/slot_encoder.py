# Single-channel wheel encoder: a slotted disk in an IR interrupter (F249 / LM393 module,
# seed 003 §3.4). Its output has no direction: count the rising edges, one per slot, in
# an IRQ ("processing signals generated from the wheel encoder ... using interrupt").
from machine import Pin, disable_irq, enable_irq


class SlotEncoder:
    def __init__(self, pin):
        self._pin = Pin(pin, Pin.IN)  # the module's comparator output has its own pull-up
        self.count = 0
        self._pin.irq(self._edge, Pin.IRQ_RISING)

    def _edge(self, _pin):
        self.count += 1


def read_counts(left, right):
    """Both running totals at one instant (an IRQ may not land between the two reads)."""
    state = disable_irq()
    counts = left.count, right.count
    enable_irq(state)
    return counts
