# IRQ handlers run in edge order, with ticks_us() equal to the edge time, and a main
# program that polls the clock sees them between its own statements.
from machine import Pin
from time import sleep_ms, ticks_diff, ticks_us

t0 = ticks_us()
events = []
a = Pin(34, Pin.IN)
b = Pin(35, Pin.IN)


def on_edge(pin):
    events.append((repr(pin), pin.value(), ticks_diff(ticks_us(), t0)))


a.irq(on_edge, Pin.IRQ_RISING | Pin.IRQ_FALLING)
b.irq(on_edge, Pin.IRQ_RISING)
sleep_ms(3)
print("R events", events)
# busy wait on the clock until a handler has run
seen = len(events)
while len(events) == seen:
    ticks_us()
print("R busy_saw", events[-1])
