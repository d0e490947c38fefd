# I2C.deinit: the machine.I2C docs name it for the WiPy only; extmod/machine_i2c.c's methods
# (machine_i2c_locals_dict_table, shared by the rp2's and the ESP32's I2C and by SoftI2C)
# have none up to 1.28, so a board's is an AttributeError; SPI and SoftSPI have one
# (extmod/machine_spi.c, machine_spi_deinit).
import sys
from machine import I2C, SPI, Pin, SoftI2C, SoftSPI

print("R version", sys.implementation.version[:2])
buses = (
    ("I2C", I2C(0)),
    ("SoftI2C", SoftI2C(scl=Pin(14), sda=Pin(15))),
    ("SPI", SPI(1)),
    ("SoftSPI", SoftSPI(sck=Pin(10), mosi=Pin(11), miso=Pin(12))),
)
for name, bus in buses:
    try:
        bus.deinit()
        print('R %s "deinit"' % name)
    except AttributeError as e:
        print("R %s" % name, ["AttributeError", str(e)])
