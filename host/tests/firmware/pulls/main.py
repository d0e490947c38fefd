# Pulls and triggers as the wire says them: unwired inputs read their pull; a button on a
# pull-down (pin 23, wired to "button") fires IRQ_RISING at the press, IRQ_FALLING at release.
from machine import Pin
from time import sleep_ms, ticks_diff, ticks_us

t0 = ticks_us()
print("R up", Pin(4, Pin.IN, Pin.PULL_UP).value())
print("R down", Pin(5, Pin.IN, Pin.PULL_DOWN).value())
print("R floating", Pin(12, Pin.IN).value())
drain = Pin(13, Pin.OPEN_DRAIN, value=1)
events = []


def on_edge(pin):
    events.append((pin.irq().flags(), ticks_diff(ticks_us(), t0) // 1000))


button = Pin(23, Pin.IN, Pin.PULL_DOWN)
button.irq(on_edge, Pin.IRQ_RISING)
sleep_ms(30)
button.irq(on_edge, Pin.IRQ_FALLING)
sleep_ms(30)
print("R events", events)
