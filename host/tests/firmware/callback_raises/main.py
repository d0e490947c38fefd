# A Timer callback with a bug: a board prints its traceback and goes on without it.
import time
from machine import Timer


def tick(t):
    raise ValueError("bad reading")


Timer(0, period=100, callback=tick)
while True:
    time.sleep_ms(10)
