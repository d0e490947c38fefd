# Dead reckoning from the slot counts (seed 002 §6.1, App. B.2 in unicycle form): each
# wheel's travel is its count times MM_PER_TICK, signed by the commanded direction (the
# encoders cannot tell); the pose moves along the mid heading. The 90-degree override
# (§5.7, "the embedded code was altered to update the odometry to ensure that the angle of
# the robot changed by 90°") replaces a spin's measured turn with exactly 90 degrees.
import math

SLOTS_PER_WHEEL_REV = 480  # 16 slots on the motor shaft, 30:1 gearbox
WHEEL_DIAMETER_MM = 60.0
TRACK_MM = 180.0
MM_PER_TICK = math.pi * WHEEL_DIAMETER_MM / SLOTS_PER_WHEEL_REV
HALF_PI = math.pi / 2


class Odometry:
    def __init__(self, x_mm=0.0, y_mm=0.0, theta=0.0):
        self.x_mm, self.y_mm, self.theta = x_mm, y_mm, theta
        self.spin_start = None  # heading when the current spin began

    def update(self, ticks_l, ticks_r):
        """Signed tick counts of one control period."""
        dl, dr = ticks_l * MM_PER_TICK, ticks_r * MM_PER_TICK
        d = (dl + dr) / 2
        dth = (dr - dl) / TRACK_MM
        mid = self.theta + dth / 2
        self.x_mm += d * math.cos(mid)
        self.y_mm += d * math.sin(mid)
        self.theta += dth

    def begin_spin(self):
        self.spin_start = self.theta

    def end_spin(self, direction, override):
        """A spin of 90 degrees ``direction`` (+1 left, -1 right) ended: with ``override``
        the heading is set to exactly 90 degrees from where the spin began."""
        if override and self.spin_start is not None:
            self.theta = self.spin_start + direction * HALF_PI
        self.spin_start = None

    def along(self, px, py, hx, hy):
        """How far the robot is past the point (px, py) along the unit vector (hx, hy)."""
        return (self.x_mm - px) * hx + (self.y_mm - py) * hy
