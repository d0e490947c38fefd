# Left-wall following (seed 004 §2.4, SCurveBot.cpp asn4 and Algorithm 3): drive at a
# constant 400 mm/s and turn to keep the nearest wall abeam. From the sonar reading
# (r, theta) of the nearest object, the error is theta - 90 deg for a wall on the left
# (theta + 90 on the right); outside the dead band the rotational velocity is
# 0.125 deg/s per degree of error. The walk ends when no wall is seen ("nowall").
#
# The seed's robot gets (r, theta) from Aria's checkRangeDevicesCurrentPolar over its
# sonar ring; this robot has two sonars on its left, abeam and 45 degrees forward, and
# finds the nearest point of the wall as the seed says SonarBot does, by triangulation:
# the wall is the line through the two echoes, its nearest point the foot of the
# perpendicular from the robot's centre. Pure Python. Lengths in mm, angles in deg.
import math

try:
    from micropython import const
except ImportError:  # CPython

    def const(x):
        return x


SPEED_MM_S = 400.0  # ArActionConstantVelocity("Constant Velocity", 400)
GAIN_PER_S = 0.125  # "set Rotational Velocity = angle(.125)": deg/s per degree
DEAD_BAND_DEG = 1.0  # the seed's delta-theta, not given: about one reading's noise
BODY_RADIUS_MM = 140.0  # both left sonars sit on the rim of the 280 mm body
SONAR_L_MOUNT = (0.0, BODY_RADIUS_MM, 90.0)  # x forward, y left (mm), axis (deg)
SONAR_LF_MOUNT = (BODY_RADIUS_MM * 0.70710678, BODY_RADIUS_MM * 0.70710678, 45.0)
NOWALL_MM = 2500.0  # an abeam reading beyond this is no wall (the canyon is 1.2 m wide)
NOWALL_READINGS = const(2)  # in a row: the end of the canyon
FRONT_STOP_MM = 300.0  # something this near ahead: stop (Aria keeps the robot off it)


def echo_point(mount, range_mm):
    """Where an echo came from, in the robot's frame (mm)."""
    mx, my, axis_deg = mount
    a = math.radians(axis_deg)
    return mx + range_mm * math.cos(a), my + range_mm * math.sin(a)


def nearest_wall(r_l_mm, r_lf_mm):
    """(range_mm, bearing_deg) of the nearest point of the wall through both echoes,
    seen from the robot's centre; None if the two echoes are one point."""
    x1, y1 = echo_point(SONAR_L_MOUNT, r_l_mm)
    x2, y2 = echo_point(SONAR_LF_MOUNT, r_lf_mm)
    dx, dy = x2 - x1, y2 - y1
    den = dx * dx + dy * dy
    if den < 1.0:
        return None
    t = -(x1 * dx + y1 * dy) / den
    fx, fy = x1 + t * dx, y1 + t * dy
    return math.sqrt(fx * fx + fy * fy), math.degrees(math.atan2(fy, fx))


def rotation_deg_s(bearing_deg):
    """Algorithm 3: the rotational velocity that turns the nearest wall abeam."""
    side = 1 if bearing_deg < 0 else 0  # right: 1, left: 0
    angle = bearing_deg + (2 * side - 1) * 90
    return GAIN_PER_S * angle if abs(angle) > DEAD_BAND_DEG else 0.0


class WallFollow:
    """``step(r_front, r_left, r_left_front)`` with the newest readings (mm, None for no
    echo) returns (v_mm_s, w_deg_s); ``done`` once no wall has been seen for
    NOWALL_READINGS readings in a row. Called once per sonar reading."""

    def __init__(self):
        self.done = False
        self.bearing_deg = None
        self._nowall = 0
        self.w_deg_s = 0.0

    def step(self, r_front_mm, r_l_mm, r_lf_mm):
        if self.done:
            return 0.0, 0.0
        self._nowall = self._nowall + 1 if r_l_mm is None or r_l_mm > NOWALL_MM else 0
        if self._nowall >= NOWALL_READINGS:
            self.done = True
            return 0.0, 0.0
        wall = None
        if not self._nowall and r_lf_mm is not None and r_lf_mm <= NOWALL_MM:
            wall = nearest_wall(r_l_mm, r_lf_mm)
        self.bearing_deg = wall[1] if wall else None
        self.w_deg_s = rotation_deg_s(self.bearing_deg) if wall else 0.0
        v = 0.0 if r_front_mm is not None and r_front_mm < FRONT_STOP_MM else SPEED_MM_S
        return v, self.w_deg_s
