# A button on D4 (to ground, on the pull-up) toggles the blue LED on D2 in its IRQ.
import time

from machine import Pin

led = Pin(2, Pin.OUT, value=0)
button = Pin(4, Pin.IN, Pin.PULL_UP)


def toggle(pin):
    led.value(not led.value())
    print("toggled", led.value(), time.ticks_diff(time.ticks_ms(), start))


start = time.ticks_ms()
button.irq(trigger=Pin.IRQ_FALLING, handler=toggle)
while True:
    time.sleep_ms(50)
