import asyncio
from time import ticks_diff, ticks_ms

t0 = ticks_ms()
log = []


async def ticker(name, period_ms, n):
    for _ in range(n):
        await asyncio.sleep_ms(period_ms)
        log.append((name, ticks_diff(ticks_ms(), t0)))


async def main():
    ev = asyncio.Event()

    async def setter():
        await asyncio.sleep_ms(70)
        ev.set()

    asyncio.create_task(setter())
    await asyncio.gather(ticker("a", 30, 3), ticker("b", 50, 2))
    await ev.wait()
    log.append(("event", ticks_diff(ticks_ms(), t0)))

    async def slow():
        await asyncio.sleep_ms(1000)

    try:
        await asyncio.wait_for(slow(), 0.2)
    except asyncio.TimeoutError:
        log.append(("timeout", ticks_diff(ticks_ms(), t0)))


asyncio.run(main())
print("R log", log)
