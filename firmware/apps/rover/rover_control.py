# Rover behaviour, free of hardware: cruise, slow down as the sonar range shrinks,
# and on a bump back off and turn in place. Pure Python, so CPython tests can
# import it too.
try:
    from micropython import const
except ImportError:  # CPython

    def const(x):
        return x


CRUISE_M_S = 0.30
CRAWL_M_S = 0.08  # never slower while cruising, so the bumper finds the wall
SLOW_RANGE_M = 1.0  # start slowing down below this range
STOP_RANGE_M = 0.10  # crawl speed at and below this range
BACKUP_M_S = -0.15
TURN_M_S = 0.20  # wheel rim speed while turning in place
BACKUP_STEPS = const(10)  # 0.5 s at 50 ms
TURN_STEPS = const(12)  # 0.6 s at 50 ms

CRUISE = const(0)
BACKUP = const(1)
TURN = const(2)
STATE_NAMES = ("cruise", "backup", "turn")


def cruise_speed(range_m):
    """Forward speed for a sonar range: full speed far away, crawl near a wall."""
    if range_m is None or range_m >= SLOW_RANGE_M:
        return CRUISE_M_S
    if range_m <= STOP_RANGE_M:
        return CRAWL_M_S
    frac = (range_m - STOP_RANGE_M) / (SLOW_RANGE_M - STOP_RANGE_M)
    return CRAWL_M_S + frac * (CRUISE_M_S - CRAWL_M_S)


class Rover:
    def __init__(self):
        self.state = CRUISE
        self._steps = 0
        self.bumps = 0

    def step(self, range_m, bumped):
        """One control step: returns (left, right) wheel speed targets in m/s."""
        if bumped and self.state == CRUISE:
            self.bumps += 1
            self._enter(BACKUP, BACKUP_STEPS)
        if self.state == BACKUP:
            if self._tick():
                self._enter(TURN, TURN_STEPS)
            return BACKUP_M_S, BACKUP_M_S
        if self.state == TURN:
            if self._tick():
                self._enter(CRUISE, 0)
            return TURN_M_S, -TURN_M_S
        v = cruise_speed(range_m)
        return v, v

    def _enter(self, state, steps):
        self.state = state
        self._steps = steps

    def _tick(self):
        self._steps -= 1
        return self._steps <= 0


class WheelSpeedPI:
    """Wheel speed loop: feed-forward duty plus PI on encoder counts per step."""

    def __init__(self, m_per_count, period_s, ff_per_m_s=1.85, deadband=0.08, kp=0.6, ki=0.4):
        self._m_per_count = m_per_count
        self._period_s = period_s
        self._ff = ff_per_m_s
        self._deadband = deadband
        self._kp = kp
        self._ki = ki
        self._integral = 0.0
        self.speed_m_s = 0.0

    def update(self, target_m_s, counts):
        self.speed_m_s = counts * self._m_per_count / self._period_s
        if target_m_s == 0:
            self._integral = 0.0
            return 0.0
        err = target_m_s - self.speed_m_s
        self._integral = max(-0.3, min(0.3, self._integral + err * self._ki * self._period_s * 10))
        ff = self._deadband + abs(target_m_s) * self._ff
        duty = (ff if target_m_s > 0 else -ff) + self._kp * err + self._integral
        return max(-1.0, min(1.0, duty))

    def reset(self):
        self._integral = 0.0
