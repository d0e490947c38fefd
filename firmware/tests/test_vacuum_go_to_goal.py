"""Go-to-goal of seed 003 (Appendix A.3): the pivot branch at |e| >= pi/8, the PID below
it, the wrapped heading error and the listing's unwrapped one, the derivative's time base,
the square 5 cm stop box; and the quantum scheduler of §4.1, the mission file."""

import math

import pytest
from chassis import PWM_MIN
from go_to_goal import GAIN_SETS, PIVOT_RAD, HeadingController, at_goal, wheel_pwm
from mission_config import BUGS, parse
from scheduler import QuantumScheduler

DEG = math.pi / 180


def test_the_three_gain_sets_are_the_seeds():
    """§5.1.1: figures 5.3, 5.4 and 5.5."""
    assert GAIN_SETS == ((2.0, 0.05, 0.0), (2.5, 0.5, 0.1), (20.0, 10.0, 5.0))


def test_a_goal_45_deg_to_the_left_starts_with_a_ccw_pivot_about_the_left_wheel():
    """Notes §9: (0,0) -> (150,150) from phi = 0: e = 45 deg > 22.5 deg, left 0, right PWMmin."""
    ctl = HeadingController(*GAIN_SETS[0])
    assert ctl.step(math.atan2(150, 150), 0.0, 15.0) == (0, PWM_MIN)
    assert ctl.step(-45 * DEG, 0.0, 15.0) == (PWM_MIN, 0), "clockwise about the right wheel"


def test_the_pivot_branch_starts_at_exactly_pi_over_8():
    ctl = HeadingController(*GAIN_SETS[0])
    assert ctl.step(PIVOT_RAD, 0.0, 15.0) == (0, PWM_MIN)
    pid = ctl.step(PIVOT_RAD * 0.999, 0.0, 15.0)
    assert pid != (0, PWM_MIN) and pid[1] > pid[0] > 0, "just inside: PID, turning left, both wheels on"


def test_on_heading_both_wheels_get_the_cruise_speeds_pwm():
    ctl = HeadingController(*GAIN_SETS[0])
    assert ctl.step(0.3, 0.3, 15.0) == (wheel_pwm(15.0), wheel_pwm(15.0))


def test_a_goal_just_behind_across_pi_is_a_small_error_once_wrapped():
    """Heading 170 deg, goal bearing -175 deg: 15 deg to the left. Unwrapped (as listed)
    the error is -345 deg and the robot pivots clockwise, the long way round."""
    wrapped = HeadingController(*GAIN_SETS[0])
    listed = HeadingController(*GAIN_SETS[0], no_wrap=True)
    left, right = wrapped.step(-175 * DEG, 170 * DEG, 15.0)
    assert wrapped.err == pytest.approx(15 * DEG) and right > left > 0
    assert listed.step(-175 * DEG, 170 * DEG, 15.0) == (PWM_MIN, 0)
    assert listed.err == pytest.approx(-345 * DEG)


def test_the_derivative_over_delta_in_ms_is_1000_times_weaker():
    """A.3 divides (e - e_old) by delta in ms while the integral uses delta / 1000."""
    seconds = HeadingController(0.0, 0.0, 5.0, delta_ms=100)
    listed = HeadingController(0.0, 0.0, 5.0, delta_ms=100, derivative_in_ms=True)
    for ctl in (seconds, listed):
        ctl.step(0.0, 0.0, 15.0)
        ctl.step(0.1, 0.0, 15.0)
    assert seconds.w == pytest.approx(5.0 * 0.1 / 0.1)
    assert listed.w == pytest.approx(seconds.w / 1000)


def test_the_integral_runs_in_both_branches_as_listed_and_resets_at_a_new_goal():
    ctl = HeadingController(0.0, 1.0, 0.0, delta_ms=100)
    ctl.step(1.0, 0.0, 15.0)  # a pivot: the sum still grows
    assert ctl.err_sum == pytest.approx(0.1)
    ctl.reset()
    assert ctl.err_sum == 0.0 and ctl.err_old == 0.0


@pytest.mark.parametrize(
    "x, y, inside",
    [(145.1, 145.1, True), (154.9, 145.1, True), (145.0, 150.0, False), (150.0, 155.0, False), (146.0, 154.0, True)],
)
def test_the_stop_box_is_a_5_cm_square_not_a_circle(x, y, inside):
    """(146, 154) is 5.7 cm away, outside a 5 cm circle, inside the square."""
    assert at_goal(x, y, 150.0, 150.0) is inside


def test_the_scheduler_runs_pose_every_2_behaviour_every_10_sensing_every_3_quanta():
    """§4.1 on a 50 ms quantum: 100, 500 and 150 ms; the ping (sensing) last."""
    sched = QuantumScheduler((("pose", 2), ("behaviour", 10), ("sense", 3)))
    plan = [sched.due() for _ in range(60)]
    for name, period_ms in (("pose", 100), ("behaviour", 500), ("sense", 150)):
        quanta = [q for q, due in enumerate(plan) if name in due]
        assert {b - a for a, b in zip(quanta, quanta[1:])} == {period_ms // 50}, name
    assert plan[0] == ("pose", "behaviour", "sense") and plan[1] == () and plan[30] == plan[0]


def test_the_mission_file_fills_in_defaults_and_names_a_bad_key():
    m = parse('{"goals": [[-150, 3]], "bugs": ["heading_no_wrap"]}')
    assert m["start"] == (0.0, 0.0, 0.0) and m["gains"] == GAIN_SETS[0] and m["goals"] == [[-150, 3]]
    assert parse("")["goals"] == ((150.0, 150.0),), "no file: the seed's first test"
    with pytest.raises(ValueError, match="goal"):
        parse('{"goal": [[1, 2]]}')
    with pytest.raises(ValueError, match="no_wrap"):
        parse('{"bugs": ["no_wrap"]}')
    assert set(BUGS) == {"mean_filter_no_reset", "heading_no_wrap", "derivative_in_ms"}
