import time

from machine import Pin

led = Pin(2, Pin.OUT)
button = Pin(4, Pin.IN, Pin.PULL_UP)
presses = 0


def pressed(pin):
    global presses
    presses += 1


button.irq(trigger=Pin.IRQ_FALLING, handler=pressed)
print("ready")
seen = 0
while True:
    if presses != seen:
        seen = presses
        led.value(not led.value())
        print("Button pressed", seen)
    time.sleep_ms(10)
