# Watches two batteries every 20 ms and lights the LED while the button is pressed. Its
# checks run only in windows of its own clock: a spare battery below LOW_U16 from 1.0 s
# to 1.5 s raises ValueError, the main battery below it from 1.5 s to 2.0 s raises
# RuntimeError (the planted failures of host/tests/test_shrink.py).
import time

from machine import ADC, Pin

LOW_U16 = 20000
batt = ADC(Pin(26))
spare = ADC(Pin(27))
button = Pin(13, Pin.IN, Pin.PULL_UP)
led = Pin(25, Pin.OUT)
start = time.ticks_ms()
while True:
    t_ms = time.ticks_diff(time.ticks_ms(), start)
    if 1000 <= t_ms < 1500 and spare.read_u16() < LOW_U16:
        raise ValueError("spare battery low at %d ms" % t_ms)
    reading = batt.read_u16()
    if 1500 <= t_ms < 2000 and reading < LOW_U16:
        raise RuntimeError("battery low: %d at %d ms" % (reading, t_ms))
    led.value(1 if button.value() == 0 else 0)
    time.sleep_ms(20)
