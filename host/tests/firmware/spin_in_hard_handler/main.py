# A hard IRQ's handler that waits for a flag only the main program could set: it never ends
# on a board either (nothing runs until it returns, and it runs at its edge's instant).
import time
from machine import Pin

ready = False


def on_a(_pin):
    while not ready:
        pass


Pin(6, Pin.IN).irq(on_a, Pin.IRQ_RISING, hard=True)
while True:
    time.sleep_ms(10)
    ready = False
