# Seed 002's duct navigation (§4.5, App. B.5, §5.5, §5.7): forward with centring, a branch
# noted while a side sonar reads 0, the duct end at the front threshold, then the
# recursive reverse: back to the last branch in the list, a little further (the overshoot
# back), a 90-degree spin towards an unexplored branch (explore it forwards) or away from
# an explored one (keep reversing), until the list is empty; then reverse home.
import math

from duct_odometry import MM_PER_TICK, TRACK_MM

CRUISE = 25  # ticks per 50 ms: 0.2 m/s (a duty step is about 5.7 ticks; duty 9 gives about 26)
STEER = 4  # centring: cruise +- this
SPIN = 16  # spin speed, ticks per period each wheel
DEAD = 8  # centring dead band, counts of L - R
CENTRED = 62  # a side reading (calibrated) with the robot centred in the 400 mm duct
HEAD_TOL = 0.07  # rad (4 deg): the odometry heading kept this close to the duct's
FRONT_NEAR = 60  # front reading at the duct end (about 120 mm)
MIN_OPEN_MM = 150  # an opening shorter than this is not a branch
SETBACK_MM = 115  # side sonars 100 mm behind the axle, plus the peak detector's lag
WAIT_STEPS = 30  # main-loop steps (10 ms) stopped before a spin
SPIN_TICKS = int(math.pi / 2 * TRACK_MM / 2 / MM_PER_TICK)  # the outer wheel's travel
HOME_MM = 0  # home: the start point passed, reversing

FORWARD = 0
REVERSE = 1
STOPPING = 2
SPINNING = 3
DONE = 4
STATE_NAMES = ("forward", "reverse", "stopping", "spinning", "done")


class Branch:
    def __init__(self, x, y, side, hx, hy):
        self.x, self.y = x, y  # where to spin, mm
        self.side = side  # +1 left, -1 right
        self.hx, self.hy = hx, hy  # the duct's forward direction where it was seen
        self.explored = False
        self.bx = self.by = 0.0  # the branch's own direction, once turned into


class Explorer:
    def __init__(self, odo, log, override=True, fix=False):
        self.odo = odo
        self.log = log
        self.override = override
        self.fix = fix
        self.branches = []
        self.found = 0
        self.ends = 0
        self.state = FORWARD
        self.hx, self.hy = 1.0, 0.0  # direction of the duct being driven (unit)
        self.angle = 0.0  # the same as an angle
        self.armed = False  # both walls seen since the last start or turn
        self.opening = None  # [side, sum_x, sum_y, n, start_x, start_y]
        self.wait = 0
        self.after_stop = None
        self.spin_dir = 0
        self.spin_from = 0
        self.target = None

    # -- helpers ----------------------------------------------------------------------

    def _centre(self, speed, left, right):
        """Bang-bang centring with a dead band (§4.5.1); with one wall only, that wall is
        held at the centred reading (the seed "tracked the remaining duct wall"). The
        odometry heading is held within HEAD_TOL of the duct's first: an amplitude sonar
        reads a wall seen at an angle as far away, and centring on it would steer into it."""
        if left and right:
            diff = left - right
        elif left:
            diff = 2 * (left - CENTRED)
        elif right:
            diff = 2 * (CENTRED - right)
        else:
            diff = 0
        err = math.atan2(math.sin(self.odo.theta - self.angle), math.cos(self.odo.theta - self.angle))
        if err > HEAD_TOL:  # turned left of the duct: clockwise, whichever way it drives
            return speed + STEER, speed - STEER
        if err < -HEAD_TOL:
            return speed - STEER, speed + STEER
        s = STEER if speed > 0 else -STEER
        if diff > DEAD:  # the left wall is closer: away from it
            return speed + s, speed - s
        if diff < -DEAD:
            return speed - s, speed + s
        return speed, speed

    def _stop_then(self, what):
        self.state = STOPPING
        self.wait = WAIT_STEPS
        self.after_stop = what
        return 0, 0

    # -- the states ----------------------------------------------------------------------

    def step(self, front, left, right, abs_l, abs_r):
        """One main-loop step: filtered readings and each wheel's total slots. Returns the
        wheels' set speeds (ticks per period, signed)."""
        if self.state == FORWARD:
            return self._forward(front, left, right)
        if self.state == REVERSE:
            return self._reverse(left, right)
        if self.state == STOPPING:
            self.wait -= 1
            if self.wait <= 0:
                self.after_stop(abs_l, abs_r)
            return 0, 0
        if self.state == SPINNING:
            return self._spinning(abs_l, abs_r)
        return 0, 0

    def _forward(self, front, left, right):
        if front >= FRONT_NEAR:
            self.ends += 1
            self.opening = None
            self.log("duct end", self.odo)
            return self._stop_then(self._start_reverse)
        if not self.armed:
            self.armed = left > 0 and right > 0
            return CRUISE, CRUISE
        if left == 0 or right == 0:
            self._note_opening(left, right)
            return self._centre(CRUISE, left, right)
        if self.opening is not None:
            self._close_opening()
        return self._centre(CRUISE, left, right)

    def _note_opening(self, left, right):
        o = self.odo
        if self.opening is None:
            side = 1 if left == 0 else -1
            self.opening = [side, 0.0, 0.0, 0, o.x_mm, o.y_mm]
        op = self.opening
        op[1] += o.x_mm
        op[2] += o.y_mm
        op[3] += 1

    def _close_opening(self):
        side, sx, sy, n, x0, y0 = self.opening
        self.opening = None
        o = self.odo
        if math.sqrt((o.x_mm - x0) ** 2 + (o.y_mm - y0) ** 2) < MIN_OPEN_MM:
            return
        cx, cy = sx / n - SETBACK_MM * self.hx, sy / n - SETBACK_MM * self.hy
        self.branches.append(Branch(cx, cy, side, self.hx, self.hy))
        self.found += 1
        self.log("branch " + ("left" if side > 0 else "right"), o, cx, cy)

    def _start_reverse(self, _abs_l=0, _abs_r=0):
        self.state = REVERSE
        self.target = self.branches[-1] if self.branches else None

    def _reverse(self, left, right):
        b, o = self.target, self.odo
        if b is None:  # the list is empty: home is the start, behind
            if o.along(0.0, 0.0, 1.0, 0.0) <= HOME_MM:
                self.state = DONE
                self.log("home", o)
                return 0, 0
        elif b.explored and o.along(b.x, b.y, b.bx, b.by) <= 0:
            return self._stop_then(self._start_spin)
        elif not b.explored and o.along(b.x, b.y, b.hx, b.hy) <= 0:
            return self._stop_then(self._start_spin)
        return self._centre(-CRUISE, left, right)

    def _start_spin(self, abs_l, abs_r):
        b = self.target
        self.spin_dir = b.side if not b.explored else -b.side
        self.spin_from = abs_r if self.spin_dir > 0 else abs_l  # the wheel going forwards
        self.odo.begin_spin()
        self.state = SPINNING

    def _spinning(self, abs_l, abs_r):
        d = self.spin_dir
        outer = abs_r if d > 0 else abs_l
        if outer - self.spin_from < SPIN_TICKS:
            return -d * SPIN, d * SPIN
        self.odo.end_spin(d, self.override)
        b = self.target
        if self.fix:
            self.odo.x_mm, self.odo.y_mm = b.x, b.y
        self.log("spin " + ("left" if d > 0 else "right"), self.odo)
        return self._stop_then(self._after_spin)

    def _after_spin(self, _abs_l, _abs_r):
        b = self.target
        if not b.explored:  # turned into it: explore it forwards
            b.explored = True
            b.bx, b.by = -b.side * b.hy, b.side * b.hx  # the duct's direction turned 90 deg to the side
            self.hx, self.hy = b.bx, b.by
            self.angle = math.atan2(b.by, b.bx)
            self.state = FORWARD
            self.armed = False
            return
        self.branches.pop()  # turned out of it: back in the duct it came from
        self.hx, self.hy = b.hx, b.hy
        self.angle = math.atan2(b.hy, b.hx)
        self._start_reverse()
