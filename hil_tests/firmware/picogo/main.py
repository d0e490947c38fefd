# Reads the line sensors three times by PIO, then three times with the CPU's pins (the
# state machine stopped and its pins made the CPU's again), each read's instant beside it.
import time
from machine import Pin

from tracker import BitBanged, Tracker

trs = Tracker()
for _ in range(3):
    print("pio", trs.read(), time.ticks_us())
trs.sm.active(0)
Pin(6, Pin.OUT)
Pin(7, Pin.OUT)
bb = BitBanged()
for _ in range(3):
    print("cpu", bb.read(), time.ticks_us())
print("done")
