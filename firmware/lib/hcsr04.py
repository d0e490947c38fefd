# HC-SR04 ultrasonic ranger read with time_pulse_us: a 10 us TRIG pulse, then the width
# of the ECHO pulse, 58.31 us per cm of range (seed 003 §3.3: D = T C / 2 at 343 m/s).
# ECHO is a 5 V output: on a 3.3 V board it goes through a divider.
from machine import Pin, time_pulse_us
from micropython import const
from time import sleep_us

US_PER_CM = 58.31  # 2 / 34300 cm/s
TRIGGER_US = const(10)  # "Trigger Input Signal 10us TTL pulse"
# The module holds ECHO high for 38 ms when nothing answers; its longest real echo is
# 4 m, 23.3 ms ("Echo pin outputs a pulse 150us to 25ms"). Waiting 25 ms keeps a ping
# under 26 ms and tells "nothing within 4 m" just as well.
ECHO_TIMEOUT_US = const(25_000)


class HCSR04:
    def __init__(self, trig, echo, echo_timeout_us=ECHO_TIMEOUT_US):
        self._trig = Pin(trig, Pin.OUT, value=0)
        self._echo = Pin(echo, Pin.IN)
        self.echo_timeout_us = echo_timeout_us

    def echo_us(self):
        """One ping: the ECHO width in us, or a negative number when no echo came
        (time_pulse_us: -2 it never rose, -1 it did not fall in time)."""
        self._trig.value(1)
        sleep_us(TRIGGER_US)
        self._trig.value(0)
        return time_pulse_us(self._echo, 1, self.echo_timeout_us)

    def distance_cm(self):
        """Range in cm, or None when nothing echoed within the timeout."""
        width_us = self.echo_us()
        if width_us < 0:
            return None
        return width_us / US_PER_CM
