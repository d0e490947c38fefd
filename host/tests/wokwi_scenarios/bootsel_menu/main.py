import time

import rp2
from machine import Pin

led = Pin("LED", Pin.OUT, value=0)


def wait_press():
    while rp2.bootsel_button():  # let go first
        time.sleep_ms(10)
    while not rp2.bootsel_button():
        time.sleep_ms(10)


print("press BOOTSEL to start")
wait_press()
led.on()
print("started")
for item in ("drive", "stop"):
    wait_press()
    print("menu:", item)
