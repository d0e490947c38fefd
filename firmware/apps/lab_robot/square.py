# The square path program (seed 004 §2.2, SquareBot.cpp asn1): four goals, each set
# once the last is achieved (Algorithm 1). The seed walks ps = {0, 2000, 2000, 0} with
# two 2-bit counters, x from 1 and y from 0, both incremented after each goal:
# (2000, 0), (2000, 2000), (0, 2000), (0, 0) mm from the start, facing +x: a
# counter-clockwise square with three +90 degree turns, ending at -90 degrees.
# Pure Python: runs on the board and under CPython.
import math

SQRDIST_MM = 2000.0  # "square shape distance is 2 meters"
PS = (0.0, SQRDIST_MM, SQRDIST_MM, 0.0)


def waypoints():
    """The goals in the order the seed's counters give them."""
    xcnt, ycnt = 1, 0
    goals = []
    for _ in range(4):
        goals.append((PS[xcnt], PS[ycnt]))
        xcnt = (xcnt + 1) & 3  # unsigned char xcnt:2
        ycnt = (ycnt + 1) & 3
    return goals


class Square:
    """Algorithm 1 over a GoTo: ``step(odometry)`` returns (v_mm_s, w_rad_s); ``goal_no``
    is the goal being driven to (1..4), ``done`` is True after the fourth."""

    def __init__(self, goto, log=print):
        self.goto = goto
        self.goals = waypoints()
        self.goal_no = 0
        self.done = False
        self._log = log

    def step(self, odo, t_ms):
        if self.done:
            return 0.0, 0.0
        if self.goal_no == 0 or self.goto.achieved():
            if self.goal_no:
                gx, gy = self.goals[self.goal_no - 1]
                self._log(
                    "goal %d (%d, %d) achieved at %d ms: x %.1f y %.1f theta %.2f deg"
                    % (self.goal_no, gx, gy, t_ms, odo.x_mm, odo.y_mm, math.degrees(odo.theta_rad))
                )
            if self.goal_no == 4:
                self.done = True
                return 0.0, 0.0
            self.goal_no += 1
            self.goto.set_goal(*self.goals[self.goal_no - 1])
        return self.goto.step(odo)
