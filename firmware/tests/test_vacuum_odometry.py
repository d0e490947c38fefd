"""The vacuum robot's odometry (seed 003 Appendix A.1) against the notes' §9 numbers:
N ticks on both wheels drive one wheel circumference, N on the right only turn by pi D / L
(forward Euler with the old heading), the heading stays in (-pi, pi], and the listing's
mean filter (never reset) overstates every step by WINDOW / (WINDOW - 1)."""

import math

import pytest
from chassis import SLOTS, TRACK_CM, WHEEL_DIAMETER_CM
from odometry import Odometry

CIRCUMFERENCE_CM = math.pi * WHEEL_DIAMETER_CM


def odometry(window=5, mean_bug=False, **kw):
    return Odometry(
        wheel_diameter_cm=WHEEL_DIAMETER_CM, slots=SLOTS, track_cm=TRACK_CM, window=window, mean_bug=mean_bug, **kw
    )


def flush(odo, left, right, window=5):
    """Hold the counts until the moving average has taken the last step in whole."""
    for _ in range(window):
        pose = odo.update(left, right)
    return pose


def test_n_ticks_on_both_wheels_drive_one_circumference_straight_on():
    odo = odometry()
    x, y, phi = flush(odo, SLOTS, SLOTS)
    assert x == pytest.approx(CIRCUMFERENCE_CM, rel=1e-12) and y == pytest.approx(0.0, abs=1e-12) and phi == 0.0


def test_n_ticks_on_the_right_only_turn_by_pi_d_over_l_and_move_half_a_turn_ahead():
    odo = odometry(window=1)  # one step: the Euler update in whole
    x, y, phi = odo.update(0, SLOTS)
    assert phi == pytest.approx(CIRCUMFERENCE_CM / TRACK_CM, rel=1e-12)
    assert (x, y) == pytest.approx((CIRCUMFERENCE_CM / 2, 0.0)), "with the old heading, 0"


def test_the_moving_average_spreads_a_step_over_the_window_and_keeps_its_whole():
    """With a window of 5 the same N right ticks come in as five fifths: five Euler steps
    of pi D / 10 along headings 0, 1/5, ... 4/5 of pi D / L."""
    odo = odometry()
    x, y, phi = flush(odo, 0, SLOTS)
    turn = CIRCUMFERENCE_CM / TRACK_CM
    step = CIRCUMFERENCE_CM / 2 / 5
    assert phi == pytest.approx(turn, rel=1e-12)
    assert x == pytest.approx(sum(step * math.cos(k * turn / 5) for k in range(5)), rel=1e-12)
    assert y == pytest.approx(sum(step * math.sin(k * turn / 5) for k in range(5)), rel=1e-12)


def test_the_heading_stays_within_minus_pi_and_pi():
    odo = odometry(phi_rad=3.0, window=1)
    _, _, phi = odo.update(0, 3)  # +0.17 rad: past pi
    assert -math.pi < phi <= math.pi and phi == pytest.approx(
        3.0 + 3 * CIRCUMFERENCE_CM / SLOTS / TRACK_CM - 2 * math.pi
    )


def steady_ratio(window, mean_bug, steps=400, ticks_per_step=3):
    """Odometry's distance over what the encoders counted, once the window is full."""
    odo = odometry(window=window, mean_bug=mean_bug)
    for k in range(1, steps + 1):
        x, _, _ = odo.update(k * ticks_per_step, k * ticks_per_step)
        if k == steps // 2:
            x_half = x
    return (x - x_half) / ((steps - steps // 2) * ticks_per_step * CIRCUMFERENCE_CM / SLOTS)


@pytest.mark.parametrize("window, bias", [(5, 1.25), (3, 1.5), (10, 1.111)])
def test_the_listed_mean_filter_overstates_steps_by_window_over_window_less_1(window, bias):
    assert steady_ratio(window, mean_bug=True) == pytest.approx(bias, abs=1e-3)


def test_the_mean_filter_as_meant_gives_every_step_in_whole():
    assert steady_ratio(5, mean_bug=False) == pytest.approx(1.000, abs=1e-9)
