# Go to a point, rotate first (seed 004 §2.2, SquareBot.cpp: ArActionGotoCust, Noah
# Harvey's change to Aria's ArActionGotoStraight). Each control step:
#   * goal achieved when the distance is under the close distance and |v| < 5 mm/s;
#   * otherwise face the goal: while the heading is off (or the robot still turns) the
#     translational velocity is 0 ("the robot will not drive straight until it is fully
#     rotated towards the desired location");
#   * then drive with the stopping-distance profile v = sqrt(2 a d), a = 200 mm/s^2,
#     capped at the top speed.
# Pure Python: runs on the board and under CPython. Lengths in mm, angles in rad.
import math

from dead_reckoning import TRACK_MM, wrap

try:
    from micropython import const
except ImportError:  # CPython

    def const(x):
        return x


DECEL_MM_S2 = 200.0  # vel = sqrt(dist * 200 * 2)
SPEED_MM_S = 400.0  # the cap. The seed's 10000 (ArActionGotoStraight("goto", 10000)) is
# no cap at all on a Pioneer; this robot's top speed is 500 mm/s at full duty, and the
# lab's other program drives at 400 mm/s (SCurveBot): the profile is capped there.
STOPPED_MM_S = 5.0  # "ArMath::fabs(myRobot->getVel() < 5)", meant as |vel| < 5 mm/s
CLOSE_MM = 10.0  # the close distance. The seed sets 0, and dist < 0 never holds: the
# goal is never achieved and the busy-wait never ends. 10 mm: one control step at the
# profile's speed there (63 mm/s x 50 ms = 3 mm) stays well inside it.
ALIGN_RAD = math.radians(1.0)  # "rotate towards goal" while the heading is further off
REALIGN_RAD = math.radians(8.0)  # driving: stop and rotate again past this
STEER_MIN_MM = 100.0  # no steering this near the goal: the bearing to a point a few mm
# away swings with every count
TURN_DECEL_RAD_S2 = DECEL_MM_S2 / (TRACK_MM / 2)  # the same 200 mm/s^2 at the wheels
TURN_RATE_RAD_S = math.radians(90.0)  # the top turn rate: 157 mm/s at the wheels
STEER_GAIN = 2.0  # rad/s per rad of heading error while driving

NO_GOAL = const(0)
ROTATE = const(1)
DRIVE = const(2)
ACHIEVED = const(3)
STATE_NAMES = ("no goal", "rotate", "drive", "achieved")


def profile_mm_s(dist_mm, decel_mm_s2=DECEL_MM_S2):
    """The seed's stopping-distance profile, sqrt(2 a d), uncapped."""
    return math.sqrt(2 * decel_mm_s2 * dist_mm) if dist_mm > 0 else 0.0


def turn_rate_rad_s(error_rad):
    """Turn rate towards a heading error: the same profile on the angle, capped."""
    rate = min(TURN_RATE_RAD_S, math.sqrt(2 * TURN_DECEL_RAD_S2 * abs(error_rad)))
    return rate if error_rad > 0 else -rate


class GoTo:
    """The go-to action: ``set_goal(x, y)``, then ``step(odometry)`` once per control
    step returns (v_mm_s, w_rad_s) to drive; ``state`` says where it is."""

    def __init__(self, close_mm=CLOSE_MM, speed_mm_s=SPEED_MM_S):
        if not close_mm > 0:
            raise ValueError("close distance must be > 0 mm, got %r: dist < close never holds" % (close_mm,))
        self.close_mm = close_mm
        self.speed_mm_s = speed_mm_s
        self.state = NO_GOAL
        self.goal = (0.0, 0.0)
        self.dist_mm = 0.0

    def set_goal(self, x_mm, y_mm):
        self.goal = (x_mm, y_mm)
        self.state = ROTATE

    def achieved(self):
        return self.state == ACHIEVED

    def step(self, odo):
        if self.state == NO_GOAL or self.state == ACHIEVED:
            return 0.0, 0.0
        dx, dy = self.goal[0] - odo.x_mm, self.goal[1] - odo.y_mm
        self.dist_mm = dist = math.sqrt(dx * dx + dy * dy)
        if dist < self.close_mm:  # "if we're close, stop"
            if abs(odo.v_mm_s) < STOPPED_MM_S and odo.w_rad_s == 0:
                self.state = ACHIEVED
            return 0.0, 0.0
        error = wrap(math.atan2(dy, dx) - odo.theta_rad)
        if self.state == DRIVE and dist > STEER_MIN_MM and abs(error) > REALIGN_RAD:
            self.state = ROTATE
        if self.state == ROTATE:
            if abs(error) > ALIGN_RAD or odo.w_rad_s != 0:
                return 0.0, (turn_rate_rad_s(error) if abs(error) > ALIGN_RAD else 0.0)
            self.state = DRIVE
        steer = STEER_GAIN * error if dist > STEER_MIN_MM else 0.0
        return min(self.speed_mm_s, profile_mm_s(dist)), steer
