# A strip of 4 NeoPixels as MicroPython's docs show (neopixel.NeoPixel, machine.bitstream):
# red, green, blue, off; 100 ms later all dim white; then one write at 400 kHz timing.
import time
from machine import Pin, bitstream

import neopixel

np = neopixel.NeoPixel(Pin(13), 4)
np[0] = (255, 0, 0)
np[1] = (0, 255, 0)
np[2] = (0, 0, 255)
t0 = time.ticks_us()
np.write()
print("R write_us", time.ticks_diff(time.ticks_us(), t0))
print("R pixel1", np[1])
print("R len", len(np))
time.sleep_ms(100)
np.fill((16, 16, 16))
np.write()
time.sleep_ms(100)
slow = neopixel.NeoPixel(Pin(13), 4, timing=0)
slow.fill((1, 0, 0))
slow.write()
time.sleep_ms(100)
try:
    bitstream(Pin(13), 1, (400, 850, 800, 450), b"\x00")
except ValueError as e:
    print("R encoding", repr(str(e)))
print("R done", 1)
