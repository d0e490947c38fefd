# An MPU6050 on an ESP32's I2C (SCL 22, SDA 21) read register by register, as the short
# drivers of public MicroPython projects do: accel in g, gyro in deg/s, temperature in C.
import struct
import time

from machine import I2C, Pin

i2c = I2C(0, scl=Pin(22), sda=Pin(21), freq=400000)
i2c.writeto_mem(0x68, 0x6B, b"\x00")  # wake up
print("ready")
while True:
    raw = i2c.readfrom_mem(0x68, 0x3B, 14)
    ax, ay, az, temp, gx, gy, gz = struct.unpack(">hhhhhhh", raw)
    print("accel: %.2f %.2f %.2f g" % (ax / 16384, ay / 16384, az / 16384))
    print("gyro: %.1f %.1f %.1f dps" % (gx / 131, gy / 131, gz / 131))
    print("temp: %.1f C" % (temp / 340 + 36.53))
    time.sleep_ms(200)
