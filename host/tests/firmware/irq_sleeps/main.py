# A handler that sleeps (a debounce written the way much public code writes it): edges
# that come meanwhile wait for it, then run in order, late; the main program waits too.
import time
from machine import Pin

t0 = time.ticks_us()
calls = []


def debounce(pin):
    calls.append(time.ticks_diff(time.ticks_us(), t0))
    time.sleep_ms(5)
    while pin.value() == 0:  # wait for the release, as such handlers do
        time.sleep_ms(1)


button = Pin(23, Pin.IN, Pin.PULL_UP)
button.irq(debounce, Pin.IRQ_FALLING)
ticks = []
for _ in range(8):
    time.sleep_ms(5)
    ticks.append(time.ticks_diff(time.ticks_us(), t0))
print("R calls", calls)
print("R main", ticks)
