# A firmware that fills its heap to the last byte, catches the MemoryError and goes on
# with the heap full: it sleeps, reads a pin and an ADC, prints, and a Timer callback and
# a pin's IRQ handler run meanwhile. None of that allocates on a board, so a board carries
# on; only then does it let the memory go and report.
import gc
import time
from machine import ADC, Pin, Timer

counts = [0, 0]  # Timer callbacks, IRQ handler calls (stored in place: no allocation)


def on_tick(_t):
    counts[0] += 1


def on_edge(_p):
    counts[1] += 1


pin = Pin(34, Pin.IN)
pin.irq(on_edge, Pin.IRQ_RISING)
adc = ADC(Pin(32))
Timer(0, mode=Timer.PERIODIC, period=10, callback=on_tick)


def fill():
    hog = None
    for _ in range(3):  # (a MemoryError's own traceback may leave a block or two: again)
        size = 4096
        while size:
            try:
                hog = (hog, bytearray(size))
            except MemoryError:
                size //= 2
    return hog


left = highs = total = t0 = elapsed = _ = 0  # (each global's slot made before the heap fills)
hog = fill()
gc.collect()
left = gc.mem_free()
t0 = time.ticks_ms()
for _ in range(50):
    time.sleep_ms(10)
    highs += pin.value()
    total += adc.read_u16()
    print("tick")
elapsed = time.ticks_diff(time.ticks_ms(), t0)
hog = None
gc.collect()
print("R left", left)
print("R elapsed", elapsed)
print("R highs", highs)
print("R total", total)
print("R ticks", counts[0])
print("R edges", counts[1])
