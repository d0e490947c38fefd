# asyncio woken from an IRQ, MicroPython's way: a ThreadSafeFlag set in a Pin handler.
# The waiting task must run at the edge's instant, not at the next poll period.
import asyncio
import time
from machine import Pin

flag = asyncio.ThreadSafeFlag()
woke = []


def on_edge(pin):
    flag.set()


async def waiter():
    t0 = time.ticks_us()
    for _ in range(3):
        await flag.wait()
        woke.append(time.ticks_diff(time.ticks_us(), t0))


async def ticker():  # another task keeps the loop polling with timeouts
    while True:
        await asyncio.sleep_ms(100)


async def main():
    asyncio.create_task(ticker())
    await waiter()


Pin(34, Pin.IN).irq(on_edge, Pin.IRQ_RISING)
asyncio.run(main())
print("R woke", woke)
