# Habits of public code that a board survives: zero-length sleeps in a polling loop, an
# asyncio task yielding with sleep(0), a str written to a UART; and the errors a board
# raises for a float in sleep_ms and a ticks interval past half the period.
import asyncio
import time
from machine import UART

t0 = time.ticks_us()
n = 0
while time.ticks_diff(time.ticks_us(), t0) < 2000:
    time.sleep_ms(0)
    n += 1
print("R zero_sleeps_end", n > 0)


async def spin():
    t0 = time.ticks_ms()
    n = 0
    while time.ticks_diff(time.ticks_ms(), t0) < 5:
        await asyncio.sleep(0)
        n += 1
    return n


print("R async_spins_end", asyncio.run(spin()) > 0)
print("R uart_str", UART(2, 9600).write("hi\n"))
try:
    time.sleep_ms(1.5)
    print("R float_ms_raises", False)
except TypeError:
    print("R float_ms_raises", True)
try:
    time.ticks_add(0, 1 << 29)
    print("R overflow", False)
except OverflowError:
    print("R overflow", True)
print("R add_edge", time.ticks_add(0, (1 << 29) - 1))
