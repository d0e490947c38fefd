# A 10 kHz Timer whose callback sleeps 20 ms: the queue stays full (later ticks are lost),
# the main loop never gets its turn again in the shim (on a board it crawls: one callback
# a pending check, docs/shim.md) and the run goes on to its end.
import time
from machine import Timer

t0 = time.ticks_ms()
runs = 0


def slow(_t):
    global runs
    runs += 1
    if runs % 25 == 0:
        print("C", runs, time.ticks_diff(time.ticks_ms(), t0))
    time.sleep_ms(20)


Timer(0, freq=10_000, callback=slow)
while True:
    print("M", time.ticks_diff(time.ticks_ms(), t0))
    time.sleep_ms(5)
