# Drivers written for older MicroPython import the u-prefixed names (an HC-SR04 driver:
# `from utime import sleep_us`); they must get the shim's modules, in virtual time.
import machine
import select
import time
import uselect
import utime
from utime import sleep_us, ticks_diff, ticks_us

import umachine

t0 = ticks_us()
sleep_us(250)
print("R slept_us", ticks_diff(ticks_us(), t0))
t0 = utime.ticks_ms()
utime.sleep_ms(40)
print("R slept_ms", utime.ticks_diff(utime.ticks_ms(), t0))
print("R same", [umachine.Pin is machine.Pin, utime is time, uselect is select])
trig = umachine.Pin(26, umachine.Pin.OUT)
trig.value(1)
sleep_us(10)
trig.value(0)
