# Reads the bench's LSM6DSOX (0x6A on i2c0) at 208 Hz output data rate: the gyro's six
# data bytes every 20 ms for 30 reads, then waits for data ready (INT1) for 20 reads.
import time
from machine import I2C, Pin

i2c = I2C(0, scl=Pin(18), sda=Pin(19), freq=400_000)
i2c.writeto_mem(0x6A, 0x11, b"\x50")  # CTRL2_G: 208 Hz
for _ in range(30):
    i2c.readfrom_mem(0x6A, 0x22, 6)
    time.sleep_ms(20)
ready = Pin(34, Pin.IN)
i2c.writeto_mem(0x6A, 0x0D, b"\x02")  # INT1_CTRL: gyro data ready
for _ in range(20):
    while not ready.value():
        time.sleep_us(100)
    i2c.readfrom_mem(0x6A, 0x22, 6)
print("R done", 1)
