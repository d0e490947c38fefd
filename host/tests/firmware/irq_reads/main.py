# A quadrature decoder as public drivers write it: the handler reads both channels on
# every edge of A while the main program sleeps. Every edge must be counted once.
import time
from machine import Pin

a = Pin(34, Pin.IN)
b = Pin(35, Pin.IN)
calls = [0]
count = [0]


def on_a(pin):
    calls[0] += 1
    count[0] += 1 if a.value() != b.value() else -1


a.irq(on_a, Pin.IRQ_RISING | Pin.IRQ_FALLING)
time.sleep_ms(1000)
print("R calls", calls[0])
print("R count", count[0])
