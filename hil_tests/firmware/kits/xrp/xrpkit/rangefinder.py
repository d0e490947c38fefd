# The HC-SR04 rangefinder: a 10 us trigger, then the echo's length at 0.0343 cm per us, there and back.
import time
from machine import Pin, time_pulse_us


class Rangefinder:
    def __init__(self, trigger="DISTANCE_TRIGGER", echo="DISTANCE_ECHO", timeout_us=30_000):
        self.trigger = Pin(trigger, Pin.OUT, value=0)
        self.echo = Pin(echo, Pin.IN)
        self.timeout_us = timeout_us

    def distance_cm(self):
        self.trigger.value(1)
        time.sleep_us(10)
        self.trigger.value(0)
        us = time_pulse_us(self.echo, 1, self.timeout_us)
        return 65535 if us < 0 else us * 0.0343 / 2
