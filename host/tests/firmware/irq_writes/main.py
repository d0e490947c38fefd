# An IRQ handler that drives an output: each edge on A is mirrored on pin 26, at the
# edge's own time, while main sleeps through all of them.
from machine import Pin
from time import sleep_ms, ticks_diff, ticks_us

t0 = ticks_us()
out = Pin(26, Pin.OUT, value=0)
a = Pin(34, Pin.IN)
b = Pin(35, Pin.IN)
seen = []


def mirror(pin):
    out.value(pin.value())
    seen.append((pin.value(), b.value(), ticks_diff(ticks_us(), t0)))


a.irq(mirror, Pin.IRQ_RISING | Pin.IRQ_FALLING)
sleep_ms(10)
print("R seen", seen)
