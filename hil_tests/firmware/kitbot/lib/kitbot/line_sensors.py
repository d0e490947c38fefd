# The line sensors: three QTR-RC channels. A reading charges each channel's capacitor (the
# pin driven high 10 us), lets the pins go and times each until it reads low (a darker
# floor returns less light: a longer time), the IR emitters lit meanwhile.
import time
from array import array
from machine import Pin, time_pulse_us
from micropython import const

TIMEOUT = const(1000)
_PINS = (16, 17, 18)


class LineSensors:
    def __init__(self):
        self.emitter = Pin(19, Pin.OUT, value=0)
        self.pins = [Pin(n, Pin.IN) for n in _PINS]
        self.data = array("H", [TIMEOUT] * len(_PINS))

    def _charge(self):
        for p in self.pins:
            p.init(Pin.OUT, value=1)
        time.sleep_us(10)

    def read(self):
        # all channels at once: let them go together, then poll until each reads low
        self.emitter.value(1)
        self._charge()
        data = self.data
        for i in range(len(data)):
            data[i] = TIMEOUT
        pins = self.pins
        for p in pins:
            p.init(Pin.IN)
        start = time.ticks_us()
        left = len(pins)
        while left:
            now = time.ticks_diff(time.ticks_us(), start)
            if now >= TIMEOUT:
                break
            for i in range(len(pins)):
                if data[i] == TIMEOUT and not pins[i].value():
                    data[i] = now
                    left -= 1
        self.emitter.value(0)
        return data

    def read_one(self, i):
        # one channel through machine.time_pulse_us (the pulse: the time it stays high)
        self.emitter.value(1)
        p = self.pins[i]
        p.init(Pin.OUT, value=1)
        time.sleep_us(10)
        p.init(Pin.IN)
        us = time_pulse_us(p, 1, TIMEOUT)
        self.emitter.value(0)
        return TIMEOUT if us < 0 else us
