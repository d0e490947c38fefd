# A device holds SDA low: each transfer times out after the bus's timeout.
import time
from machine import I2C

i2c = I2C(0, timeout=2000)
t0 = time.ticks_us()
try:
    i2c.readfrom_mem(0x6A, 0x0F, 1)
except OSError as e:
    print("R stuck", e.args[0])
print("R stuck_us", time.ticks_diff(time.ticks_us(), t0))
print("R scan", i2c.scan())
