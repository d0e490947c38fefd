# A watchdog fed every 50 ms for 250 ms, then starved: the board resets 100 ms after the
# last feed (t = 300 ms), and the firmware starts again.
import time
from machine import WDT

wdt = WDT(timeout=100)
for _ in range(5):
    wdt.feed()
    time.sleep_ms(50)
print("R fed", True)
time.sleep_ms(500)
print("R never", True)
