# Go-to-goal of seed 003 (Appendix A.3): the heading error e = phi_d - phi drives a PID
# for W while |e| < pi/8 (V kept by ensure_W as far as it can), and a pivot on one wheel
# at PWMmin beyond that; the robot stops inside a 5 cm box around the goal. The same
# controller tracks the obstacle-avoidance heading (avoidance.py). Pure Python.
#
# Flags for two bugs of the listing, both off by default (docs/vacuum.md):
#   no_wrap           e is not wrapped to (-pi, pi]: a goal behind the robot is never reached
#   derivative_in_ms  the derivative divides by delta in ms (Kd 1000 x smaller than meant)
import math

from chassis import (
    PWM_FULL,
    PWM_MAX,
    PWM_MIN,
    ROBOT_MAX_SPEED,
    ROBOT_MIN_SPEED,
    TRACK_CM,
    V_MAX,
    V_MAX_W0,
    W_MAX_V0,
)
from unicycle import arduino_map, ensure_w

PIVOT_RAD = math.pi / 8  # the branch between the PID and the pivot
STOP_BOX_CM = 5  # |Xg - x| < 5 && |Yg - y| < 5
GAIN_SETS = ((2.0, 0.05, 0.0), (2.5, 0.5, 0.1), (20.0, 10.0, 5.0))  # §5.1.1, figures 5.3-5.5


def at_goal(x, y, xg, yg):
    return abs(xg - x) < STOP_BOX_CM and abs(yg - y) < STOP_BOX_CM


def wheel_pwm(v):
    """A wheel speed as analogWrite() gets it: map() as listed, then held to 0..255 (the
    motors only run FORWARD: a negative value stops the wheel)."""
    return max(0, min(PWM_FULL, arduino_map(v, ROBOT_MIN_SPEED, ROBOT_MAX_SPEED, PWM_MIN, PWM_MAX)))


class HeadingController:
    def __init__(self, kp, ki, kd, *, delta_ms=100, no_wrap=False, derivative_in_ms=False):
        self.kp, self.ki, self.kd = kp, ki, kd
        self.delta_ms = delta_ms
        self.no_wrap = no_wrap
        self.derivative_dt = delta_ms if derivative_in_ms else delta_ms / 1000
        self.err = 0.0
        self.w = 0.0
        self.reset()

    def reset(self):
        """The listing's orphan reset (phiErrSum = 0; phiErrOld = 0): at a new goal and at
        a switch of behaviour."""
        self.err_sum = 0.0
        self.err_old = 0.0

    def step(self, phi_d, phi, v):
        """One control period: (left PWM, right PWM) for the heading set-point phi_d."""
        e = phi_d - phi
        if not self.no_wrap:
            e = math.atan2(math.sin(e), math.cos(e))
        self.err = e
        self.err_sum += e * self.delta_ms / 1000  # as listed: in both branches
        if -PIVOT_RAD < e < PIVOT_RAD:
            w = self.kp * e + self.ki * self.err_sum + self.kd * (e - self.err_old) / self.derivative_dt
            self.err_old = e
            self.w = w
            vl, vr = ensure_w(v, w, TRACK_CM, V_MAX, V_MAX_W0, W_MAX_V0)
            return wheel_pwm(vl), wheel_pwm(vr)
        if e >= PIVOT_RAD:
            return 0, PWM_MIN  # counter-clockwise, about the stopped left wheel
        return PWM_MIN, 0  # clockwise, about the right wheel
