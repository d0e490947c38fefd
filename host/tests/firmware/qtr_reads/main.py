# RC-decay reflectance sensors (QTR-xRC class) read as kit libraries read them: drive each
# line high 10 us, make it an input, and time how long it reads 1, by a loop of value()
# reads and by machine.time_pulse_us; with the IR emitters on, then off; let go as an open
# drain set high.
import time
from machine import Pin, time_pulse_us

TIMEOUT_US = 2000
emitter = Pin(26, Pin.OUT, value=0)
lines = [Pin(16, Pin.IN), Pin(17, Pin.IN)]


def read_loop(pin):
    pin.init(Pin.OUT, value=1)
    time.sleep_us(10)
    pin.init(Pin.IN)
    t0 = time.ticks_us()
    while pin.value():
        if time.ticks_diff(time.ticks_us(), t0) >= TIMEOUT_US:
            return TIMEOUT_US
    return time.ticks_diff(time.ticks_us(), t0)


def read_pulse(pin):
    pin.init(Pin.OUT, value=1)
    time.sleep_us(10)
    pin.init(Pin.IN)
    us = time_pulse_us(pin, 1, TIMEOUT_US)
    return TIMEOUT_US if us < 0 else us


emitter.value(1)
print("R loop", [read_loop(p) for p in lines])
print("R pulse", [read_pulse(p) for p in lines])
emitter.value(0)
print("R unlit_loop", [read_loop(p) for p in lines])
print("R unlit_pulse", [read_pulse(p) for p in lines])
p = lines[1]
p.init(Pin.OUT, value=1)
time.sleep_us(10)
p.init(Pin.IN)
print("R unlit_raw", time_pulse_us(p, 1, TIMEOUT_US))
# let go by an open drain's high (the pad no longer driven), read by time_pulse_us
emitter.value(1)
p = lines[0]
p.init(Pin.OUT, value=1)
time.sleep_us(10)
p.init(Pin.OPEN_DRAIN, value=1)
print("R drain_pulse", time_pulse_us(p, 1, TIMEOUT_US))
