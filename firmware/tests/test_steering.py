"""Steering by stopping a track (seed 000 eq. 7.1) and the lane-keeping law (eq. 5.13/5.14)."""

import math

import pytest
from steering import (
    DEAD_BAND_M,
    HEADING_WEIGHT_M,
    MAX_STOP_MS,
    STOP_GAIN,
    correction_ms,
    gain,
    quantise,
    stop_for_turn_ms,
    stop_ms,
    turn_rad,
)

DEG = math.pi / 180


@pytest.mark.parametrize("t_ms, deg", [(300, 1.395), (500, 3.143), (700, 5.543)])
def test_stop_turns_by_eq_7_1(t_ms, deg):
    assert turn_rad(t_ms) == pytest.approx(deg * DEG, abs=1e-5)
    assert turn_rad(-t_ms) == pytest.approx(-deg * DEG, abs=1e-5), "a left stop turns the other way"


@pytest.mark.parametrize("alpha_rad, t_ms", [(0.0599, 527), (0.0192, 256)])
def test_inverse_of_eq_7_1_gives_the_intended_alignment_stop(alpha_rad, t_ms):
    """Run_Cross's alignment: 527 ms for the 8 m pool, 256 ms for 25 m (the code's
    1.634e-4 divisor gave 52 and 25 ms)."""
    assert stop_for_turn_ms(alpha_rad) == pytest.approx(t_ms, abs=1.0)


@pytest.mark.parametrize(
    "error_m, lam", [(0.0, 401), (0.05, 391), (0.1, 381), (0.3, 341), (1.0, 201), (2.0, 1), (3.0, 201)]
)
def test_gain_follows_eq_5_14(error_m, lam):
    assert gain(error_m) == pytest.approx(lam)
    assert gain(-error_m) == pytest.approx(lam)


def test_no_correction_inside_the_5cm_dead_band():
    assert correction_ms(DEAD_BAND_M, 0.05) == 0.0 and correction_ms(-0.049, -0.1) == 0.0


def test_correction_sign_stops_the_track_on_the_side_to_turn_to():
    """Too far from the reference wall (e > 0): negative, stop the left track."""
    assert correction_ms(0.3, 0.0) == pytest.approx(-341 * 0.3)
    assert correction_ms(-0.3, 0.0) == pytest.approx(341 * 0.3)
    assert correction_ms(0.1, -0.1 / HEADING_WEIGHT_M) == pytest.approx(0.0), "on the sliding line: no turn"


@pytest.mark.parametrize(
    "raw, ms", [(0, 0), (24.9, 0), (25, 50), (-74, -50), (76, 100), (290, 300), (1000, 300), (-5000, -300)]
)
def test_stops_are_whole_50ms_quanta_at_most_300ms(raw, ms):
    assert quantise(raw) == ms


def test_stop_is_the_correction_times_the_gain():
    assert stop_ms(60) == quantise(STOP_GAIN * 60) == 100
    assert abs(stop_ms(-10_000)) == MAX_STOP_MS
