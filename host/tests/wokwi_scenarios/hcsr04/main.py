# An HC-SR04 on a Pico, read as public MicroPython examples do: a 10 us TRIG pulse, the
# ECHO pulse's width by time_pulse_us, 58 us per cm; the LED lights under 50 cm.
import time

from machine import Pin, time_pulse_us

trig = Pin(3, Pin.OUT)
echo = Pin(2, Pin.IN)
led = Pin(25, Pin.OUT)
print("ready")
while True:
    trig.value(0)
    time.sleep_us(2)
    trig.value(1)
    time.sleep_us(10)
    trig.value(0)
    width_us = time_pulse_us(echo, 1, 30000)
    cm = round(width_us / 58.31)
    led.value(1 if 0 < cm < 50 else 0)
    print("Distance:", cm, "cm")
    time.sleep_ms(100)
