# The master: every 20 ms, reads the MCU's counter (registers 0..1) and writes a command
# (register 8) with readfrom_mem / writeto_mem, as a Linux master's smbus calls would.
import time
from machine import I2C, Pin

i2c = I2C(0, scl=Pin(18), sda=Pin(19), freq=400000)
ADDR = 0x42
print("master scan", i2c.scan())
for n in range(10):
    count = int.from_bytes(i2c.readfrom_mem(ADDR, 0, 2), "little")
    print("master read", count, "at", time.ticks_us())
    i2c.writeto_mem(ADDR, 8, bytes((n,)))
    time.sleep_ms(20)
try:
    i2c.readfrom(0x43, 1)
except OSError as e:
    print("master nobody at 0x43", e.args[0])
print("master done")
while True:
    time.sleep_ms(100)
