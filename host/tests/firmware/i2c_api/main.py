# The I2C API against the bench's LSM6DSOX (0x6A on i2c0) and nothing at 0x50.
import time
from machine import I2C, Pin, SoftI2C

i2c = I2C(0, scl=Pin(18), sda=Pin(19), freq=400_000)
print("R scan", i2c.scan())
t0 = time.ticks_us()
who = i2c.readfrom_mem(0x6A, 0x0F, 1)
print("R who", list(who))
print("R who_us", time.ticks_diff(time.ticks_us(), t0))
try:
    i2c.readfrom(0x50, 1)
except OSError as e:
    print("R missing", e.args[0])
try:
    i2c.writeto(0x50, b"\x00")
except OSError as e:
    print("R missing_write", e.args[0])
i2c.writeto_mem(0x6A, 0x11, b"\x40")  # CTRL2_G: 104 Hz
print("R ctrl2", list(i2c.readfrom_mem(0x6A, 0x11, 1)))
i2c.writeto(0x6A, b"\x10\x40\x40")  # CTRL1_XL, CTRL2_G by auto-increment
buf = bytearray(2)
i2c.readfrom_mem_into(0x6A, 0x10, buf)
print("R ctrl12", list(buf))
i2c.writevto(0x6A, (b"\x0d", b"\x02"))  # INT1_CTRL: gyro data ready
i2c.writeto(0x6A, b"\x0d", False)
print("R int1", list(i2c.readfrom(0x6A, 1)))
print("R writeto", i2c.writeto(0x6A, b"\x0d\x02"))
time.sleep_ms(20)
print("R status", list(i2c.readfrom_mem(0x6A, 0x1E, 1)))
raw = i2c.readfrom_mem(0x6A, 0x28, 6)
print("R az", (raw[4] | raw[5] << 8))
print("R status_after", list(i2c.readfrom_mem(0x6A, 0x1E, 1)))
print("R mem16", list(i2c.readfrom_mem(0x6A, 0x0F, 1, addrsize=16)))
soft = SoftI2C(scl=Pin(5), sda=Pin(4), freq=100_000)
print("R soft_scan", soft.scan())
soft.start()
acks = soft.write(bytes((0x68 << 1, 0x75)))
soft.start()
soft.write(bytes((0x68 << 1 | 1,)))
b = bytearray(1)
soft.readinto(b)
soft.stop()
print("R soft_who", [acks, b[0]])
soft.start()
print("R soft_nack", soft.write(bytes((0x50 << 1, 0))))
soft.stop()
try:
    soft.readfrom(0x51, 1)
except OSError as e:
    print("R soft_missing", e.args[0])
try:
    I2C(3)
except ValueError as e:
    print("R bad_id", repr(str(e)))
