# A robust firmware: it allocates until MemoryError, catches it, frees half of what it
# took (once it has backed off a moment, its heap still full) and goes on as a board does:
# sleeps, prints, reads a pin and an ADC, starts a Timer.
import gc
import time
from machine import ADC, Pin, Timer

hog = [None] * 2048  # room for 512K, a quarter K at a time
taken = i = 0  # (each global's slot made before the heap fills)
try:
    while taken < len(hog):
        hog[taken] = bytearray(256)
        taken += 1
except MemoryError:
    print("out of memory: backing off")
    time.sleep_ms(5)
for i in range(taken // 2, taken):
    hog[i] = None
gc.collect()
print("R taken", taken)
ticks = []
timer = Timer(0, mode=Timer.PERIODIC, period=20, callback=lambda t: ticks.append(time.ticks_ms()))
pin = Pin(34, Pin.IN)
adc = ADC(Pin(32))
levels = []
reads = []
t0 = time.ticks_ms()
for _ in range(10):
    time.sleep_ms(10)
    levels.append(pin.value())
    reads.append(adc.read_u16())
timer.deinit()
print("R elapsed", time.ticks_diff(time.ticks_ms(), t0))
print("R levels", levels)
print("R reads", reads)
print("R ticks", len(ticks))
print("R kept", sum(1 for x in hog if x is not None))
