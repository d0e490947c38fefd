# asyncio's early-exit fix (extmod/asyncio/core.py, run_until_complete; MicroPython 1.26):
# the main task waits on an Event that a Timer callback sets 50 ms later, no other task, no
# stream. Before 1.26 the scheduler finds no task queued and nothing to poll and returns at
# once (asyncio.run gives None, the main task unfinished); from 1.26 it polls every 3 ms
# until the callback has set the Event and the main task has returned.
import asyncio
import sys
import time
from machine import Timer

ev = asyncio.Event()


def on_timer(_t):
    ev.set()


async def main():
    Timer(-1, mode=Timer.ONE_SHOT, period=50, callback=on_timer)
    await ev.wait()
    return "set"


t0 = time.ticks_ms()
got = asyncio.run(main())
print("R version", sys.implementation.version[:2])
print("R run", [got, time.ticks_diff(time.ticks_ms(), t0)])
