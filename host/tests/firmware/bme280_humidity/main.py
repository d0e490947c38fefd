# The BME280 driver published on PyPI (micropython-bme280, unchanged, from build/drivers/)
# as its README sets it up, read twice: its compensated humidity (Q22.10 %RH), its raw
# readings, and the humidity calibration registers as the driver reads them; then the
# chip's humidity output after a forced conversion with osrs_h skipped (ctrl_hum 0).
import time
from machine import I2C, Pin

import bme280

i2c = I2C(0, sda=Pin(4), scl=Pin(5))
bme = bme280.BME280(i2c=i2c, address=0x76)
print("R dig_h", [bme.dig_H1, bme.dig_H2, bme.dig_H3, bme.dig_H4, bme.dig_H5, bme.dig_H6])
temperature, pressure, humidity = bme.read_compensated_data()
print("R temperature_c", temperature / 100)
print("R humidity_q10", humidity)
raw = [0, 0, 0]
bme.read_raw_data(raw)
print("R raw", raw)
print("R values", list(bme.values))
i2c.writeto_mem(0x76, 0xF2, b"\x00")  # osrs_h skipped ...
i2c.writeto_mem(0x76, 0xF4, b"\x25")  # ... taken at this write of ctrl_meas (forced, x1, x1)
time.sleep_ms(10)
print("R skipped", list(i2c.readfrom_mem(0x76, 0xFD, 2)))
i2c.writeto_mem(0x76, 0xF2, b"\x01")  # a write of ctrl_hum alone changes nothing yet
i2c.writeto_mem(0x76, 0xF4, b"\x24")  # (sleep mode: ctrl_meas written, no conversion)
print("R after_sleep", list(i2c.readfrom_mem(0x76, 0xFD, 2)))
i2c.writeto_mem(0x76, 0xF4, b"\x25")
time.sleep_ms(10)
print("R measured", list(i2c.readfrom_mem(0x76, 0xFD, 2)))
