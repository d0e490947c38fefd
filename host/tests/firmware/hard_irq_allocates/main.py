# A hard IRQ's handler that computes a float (a board's float is an object on its heap):
# on a board, MemoryError at the first edge (the heap is locked in the handler).
import time
from machine import Pin

speed = [0.0]


def on_edge(pin):
    speed[0] = 1.0 / (time.ticks_us() + 1)


Pin(5, Pin.IN).irq(on_edge, Pin.IRQ_RISING, hard=True)
time.sleep_ms(20)
print("R done", True)
