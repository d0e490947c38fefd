# Odometry of seed 003 (Appendix A.1, "odometry()"), called every 100 ms with the tick
# counts of the two slotted-disk encoders: distance per wheel, a moving average over the
# last WINDOW periods (the "mean filter"), then a forward-Euler step with the old
# heading and the heading wrapped with atan2. Pure Python: CPython tests import it too.
#
# The listing never resets meanDl/meanDr before summing the window (they are globals),
# so each "mean" is (last mean + window sum) / WINDOW: in steady state the increments are
# WINDOW / (WINDOW - 1) too large (x1.25 for 5). mean_bug=True reproduces that; the
# default resets them, as the filter was meant.
import math

try:
    from micropython import const
except ImportError:  # CPython

    def const(x):
        return x


WINDOW = const(5)  # ARRAYSIZE: not in the seed, chosen here (docs/vacuum.md)


class Odometry:
    def __init__(
        self, x_cm=0.0, y_cm=0.0, phi_rad=0.0, *, wheel_diameter_cm, slots, track_cm, window=WINDOW, mean_bug=False
    ):
        self.x = float(x_cm)
        self.y = float(y_cm)
        self.phi = float(phi_rad)
        self.cm_per_tick = math.pi * wheel_diameter_cm / slots  # Dl = ticks / numberOfHole * PI * diameter
        self.track_cm = float(track_cm)  # L
        self.mean_bug = mean_bug
        self._arr_l = [0.0] * window
        self._arr_r = [0.0] * window
        self._mean_l = 0.0
        self._mean_r = 0.0
        self._prev_l = 0  # the ISR counters start at 0
        self._prev_r = 0

    def update(self, left_ticks, right_ticks):
        """One pose update from the encoders' running totals; returns (x, y, phi)."""
        dl = (left_ticks - self._prev_l) * self.cm_per_tick
        dr = (right_ticks - self._prev_r) * self.cm_per_tick
        self._prev_l, self._prev_r = left_ticks, right_ticks
        arr_l, arr_r = self._arr_l, self._arr_r
        n = len(arr_l)
        for i in range(n - 1):  # shift left by one, append the newest
            arr_l[i] = arr_l[i + 1]
            arr_r[i] = arr_r[i + 1]
        arr_l[n - 1] = dl
        arr_r[n - 1] = dr
        if not self.mean_bug:
            self._mean_l = 0.0
            self._mean_r = 0.0
        for i in range(n):
            self._mean_l += arr_l[i]
            self._mean_r += arr_r[i]
        self._mean_l /= n
        self._mean_r /= n
        dc = (self._mean_l + self._mean_r) / 2
        self.x += dc * math.cos(self.phi)  # the old heading (forward Euler)
        self.y += dc * math.sin(self.phi)
        phi = self.phi + (self._mean_r - self._mean_l) / self.track_cm
        self.phi = math.atan2(math.sin(phi), math.cos(phi))
        return self.x, self.y, self.phi
