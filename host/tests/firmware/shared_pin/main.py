# Three pins on one encoder line, each with its own IRQ handler, and one long sleep:
# every edge must reach every handler, however the host splits the batch.
from machine import Pin
from time import sleep_ms

counts = [0, 0, 0]


def counter(i):
    def on_edge(pin):
        counts[i] += 1

    return on_edge


pins = [Pin(n, Pin.IN) for n in (34, 35, 36)]
for i, pin in enumerate(pins):
    pin.irq(counter(i), Pin.IRQ_RISING | Pin.IRQ_FALLING)
sleep_ms(200)
print("R counts", counts)
