# Code that proves its loop allocates nothing: with the heap locked it prints (several
# items, sep and end), reads the clock right after (the print sends the next read to the
# host), and polls a stream an IRQ handler makes ready (an asyncio ThreadSafeFlag).
import asyncio
import micropython
import select
import time
from machine import Pin

flag = asyncio.ThreadSafeFlag()


def on_edge(pin):
    flag.set()


Pin(34, Pin.IN).irq(on_edge, Pin.IRQ_RISING)
poller = select.poll()
poller.register(flag, select.POLLIN)


def locked():
    t0 = time.ticks_us()
    micropython.heap_lock()
    print("R", "items", 3)
    print("R ends", end=" ")
    print(1, 2, 3, 4, 5, 6, sep="")
    read_us = time.ticks_diff(time.ticks_us(), t0)
    ready = 0
    for _obj, _events in poller.ipoll(1000):
        ready += 1
    woke_us = time.ticks_diff(time.ticks_us(), t0)
    micropython.heap_unlock()
    return read_us, ready, woke_us


read_us, ready, woke_us = locked()
print("R read_us", read_us)
print("R ready", ready)
print("R woke_us", woke_us)
