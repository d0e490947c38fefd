# A DHT11 on GP28 read with MicroPython's dht module once a second; each read's length
# printed beside its values: "dht <C> <%> <us>", or "dht error <errno>".
import time

import dht
from machine import Pin

sensor = dht.DHT11(Pin(28))
for _ in range(3):
    t0 = time.ticks_us()
    try:
        sensor.measure()
        print("dht", sensor.temperature(), sensor.humidity(), time.ticks_diff(time.ticks_us(), t0))
    except OSError as e:
        print("dht error", e.args[0], time.ticks_diff(time.ticks_us(), t0))
    time.sleep_ms(1000)
print("done")
while True:
    time.sleep_ms(100)
