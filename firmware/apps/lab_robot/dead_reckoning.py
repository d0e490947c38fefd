# Dead reckoning from the wheel encoders (seed 004 §1.1-1.2): each wheel's travel is
# S = R mu (net counts) (Eq. 4), and per control step the robot's travel and heading
# change are Eq. 1, S = (S_R + S_L) / 2 and theta = (S_R - S_L) / w, summed into the
# pose by Eq. 2-3. Velocities are the finite differences of Eq. 5 with S(-dt) = 0.
# Pure Python: runs on the board and under CPython. Lengths in mm, angles in rad.
import math

try:
    from micropython import const
except ImportError:  # CPython

    def const(x):
        return x


WHEEL_RADIUS_MM = 35.0  # R (the seed gives none: the lab robot's wheels)
TRACK_MM = 200.0  # w, "the distance between the contact points of the wheels"
COUNTS_PER_REV = const(80)  # 10-line disk on the motor shaft, 2:1 to the wheel, 4 edges a line
MU_RAD = 2 * math.pi / COUNTS_PER_REV  # encoder resolution, radians per pulse
MM_PER_COUNT = WHEEL_RADIUS_MM * MU_RAD  # R mu: 2.75 mm


def wrap(angle_rad):
    """The angle in -pi .. pi."""
    return math.atan2(math.sin(angle_rad), math.cos(angle_rad))


class Odometry:
    """The pose (x_mm, y_mm, theta_rad) summed from wheel increments, and the speeds of
    the last step (v_mm_s along the path, w_rad_s turning)."""

    def __init__(self, x_mm=0.0, y_mm=0.0, theta_rad=0.0, track_mm=TRACK_MM):
        self.x_mm = x_mm
        self.y_mm = y_mm
        self.theta_rad = theta_rad
        self.track_mm = track_mm
        self.s_l_mm = 0.0  # S_L(t), S_R(t): each wheel's travel since the start
        self.s_r_mm = 0.0
        self.v_mm_s = 0.0
        self.w_rad_s = 0.0

    def update(self, ds_l_mm, ds_r_mm, dt_ms):
        """One step: the wheels travelled ds_l_mm, ds_r_mm in dt_ms."""
        self.s_l_mm += ds_l_mm
        self.s_r_mm += ds_r_mm
        ds = (ds_r_mm + ds_l_mm) / 2  # Eq. 1
        dth = (ds_r_mm - ds_l_mm) / self.track_mm
        mid = self.theta_rad + dth / 2  # the chord of a step at constant wheel speeds
        self.x_mm += ds * math.cos(mid)  # Eq. 2 (the seed leaves open which heading)
        self.y_mm += ds * math.sin(mid)
        self.theta_rad = wrap(self.theta_rad + dth)
        if dt_ms > 0:  # Eq. 5
            self.v_mm_s = ds * 1000 / dt_ms
            self.w_rad_s = dth * 1000 / dt_ms

    def update_counts(self, n_l, n_r, dt_ms):
        """One step from net encoder counts (Eq. 4: S = R mu n)."""
        self.update(n_l * MM_PER_COUNT, n_r * MM_PER_COUNT, dt_ms)
