# Watches the main battery every 20 ms and lights the LED while the button is pressed.
# Its low-battery check runs only from 1.5 s to 2.0 s after start: a reading below
# LOW_U16 there raises (the planted failure of host/tests/test_shrink.py).
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
    reading = batt.read_u16()
    if 1500 <= t_ms < 2000 and reading < LOW_U16:
        raise RuntimeError("battery low: %d at %d ms" % (reading, t_ms))
    led.value(1 if button.value() == 0 else 0)
    time.sleep_ms(20)
