# Link round-trip probe: every iteration writes a pin (an actuator change) and
# sleeps, so each one costs exactly one WAIT/STATE exchange with the host.
from machine import Pin
from time import sleep_us

probe = Pin(15, Pin.OUT, value=0)
while True:
    probe.toggle()
    sleep_us(100)
