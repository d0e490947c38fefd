# A DHT22 on D15 read with MicroPython's dht module every 2 s (as its datasheet asks), a
# KY-040's switch on D25 polled; printed as "temp <C> hum <%>" and "sw <level>".
import time

import dht
from machine import Pin

sensor = dht.DHT22(Pin(15))
sw = Pin(25, Pin.IN, Pin.PULL_UP)
last_sw = sw.value()
next_read = time.ticks_ms()
while True:
    if time.ticks_diff(time.ticks_ms(), next_read) >= 0:
        sensor.measure()
        print("temp %.1f hum %.1f" % (sensor.temperature(), sensor.humidity()))
        next_read = time.ticks_add(next_read, 2000)
    if sw.value() != last_sw:
        last_sw = sw.value()
        print("sw", last_sw)
    time.sleep_ms(10)
