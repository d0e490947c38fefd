# The BME280 driver published on PyPI (micropython-bme280, unchanged, from build/drivers/)
# on whichever of the chip's two addresses answers, as its README sets it up; it prints
# the chip's id, the driver's compensated temperature and pressure, and the raw readings.
from machine import I2C, Pin

import bme280

i2c = I2C(0, sda=Pin(4), scl=Pin(5))
address = [a for a in i2c.scan() if a in (0x76, 0x77)][0]
print("R chip_id", i2c.readfrom_mem(address, 0xD0, 1)[0])
bme = bme280.BME280(i2c=i2c, address=address)
temperature, pressure, humidity = bme.read_compensated_data()
print("R temperature_c", temperature / 100)
print("R pressure_pa", pressure / 256)
raw = [0, 0, 0]
bme.read_raw_data(raw)
print("R raw", raw)
print("R values", repr(bme.values))
