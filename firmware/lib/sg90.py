# SG90 hobby servo on a 50 Hz PWM: 0.5 ms of pulse for 0 deg to 2.5 ms for 180 deg. It
# turns at 0.12 s per 60 deg (seed 003 §3.3), so the driver knows when it has arrived:
# a reading taken before then looks along whatever angle the horn has reached.
from machine import PWM, Pin
from micropython import const
from time import ticks_add, ticks_diff, ticks_ms

FREQ_HZ = const(50)
MIN_PULSE_NS = const(500_000)
MAX_PULSE_NS = const(2_500_000)
RANGE_DEG = const(180)
MS_PER_60_DEG = const(120)  # "SG90, takes 0.12 sec / 60 degrees"


def travel_ms(from_deg, to_deg):
    """Time the horn needs between two angles: 35 deg takes 70 ms."""
    return (abs(to_deg - from_deg) * MS_PER_60_DEG + 59) // 60


class SG90:
    def __init__(self, pin, start_deg=90):
        self._pwm = PWM(Pin(pin, Pin.OUT), freq=FREQ_HZ)
        self.angle_deg = None  # unknown at power-up
        self._settled_ms = ticks_ms()
        self.move(start_deg)

    def move(self, angle_deg):
        """Command an angle; returns the travel time in ms (the worst, 180 deg, when the
        horn's position was unknown)."""
        angle_deg = max(0, min(RANGE_DEG, angle_deg))
        self._pwm.duty_ns(MIN_PULSE_NS + (MAX_PULSE_NS - MIN_PULSE_NS) * angle_deg // RANGE_DEG)
        t_ms = travel_ms(0, RANGE_DEG) if self.angle_deg is None else travel_ms(self.angle_deg, angle_deg)
        self._settled_ms = ticks_add(ticks_ms(), t_ms)
        self.angle_deg = angle_deg
        return t_ms

    def settled(self):
        return ticks_diff(ticks_ms(), self._settled_ms) >= 0
