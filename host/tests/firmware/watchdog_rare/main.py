# A main loop that feeds its watchdog every second until, two minutes in, a stuck sensor
# read stops it; the watchdog (10 s) resets the board and it starts again: a reset every
# 130 s of running, for as long as the board is on.
import time
from machine import WDT

wdt = WDT(timeout=10_000)
print("boot")
for _ in range(120):
    wdt.feed()
    time.sleep_ms(1000)
while True:  # stuck
    time.sleep_ms(1000)
