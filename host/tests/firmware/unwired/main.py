# A status LED on a pin wired to nothing, and the probe pin toggled every 10 ms.
from machine import Pin
from time import sleep_ms

led = Pin(2, Pin.OUT, value=0)
probe = Pin(15, Pin.OUT, value=0)
for i in range(5):
    led.value(i % 2)
    probe.toggle()
    sleep_ms(10)
