"""The vacuum robot's unicycle model (seed 003 §4.2.1, A.2), its ICC (§2.2), ensure_W
(A.3) and the speed-to-PWM map, against the numbers of the seed 003 notes §9."""

import pytest
from chassis import PWM_FULL, PWM_MAX, PWM_MIN, ROBOT_MAX_SPEED, ROBOT_MIN_SPEED
from go_to_goal import wheel_pwm
from unicycle import arduino_map, diff_to_uni, ensure_w, icc_radius, uni_to_diff


def test_uni_to_diff_gives_vr_20_and_vl_0_for_v_10_w_1_on_a_20_cm_axle():
    assert uni_to_diff(10.0, 1.0, 20.0) == (0.0, 20.0)


@pytest.mark.parametrize("v, w", [(10.0, 1.0), (15.0, -2.0), (0.0, 3.0), (-7.5, 0.25)])
def test_diff_to_uni_undoes_uni_to_diff_exactly(v, w):
    assert diff_to_uni(*uni_to_diff(v, w, 20.0), 20.0) == (v, w)


def test_a_stopped_left_wheel_turns_about_it_at_r_l_over_2_not_2l():
    """§2.2 case 3: "rotation about the left wheel. In this case R = 2l" is an erratum."""
    assert icc_radius(0.0, 12.0, 20.0) == 10.0
    assert icc_radius(12.0, 0.0, 20.0) == -10.0
    assert icc_radius(-5.0, 5.0, 20.0) == 0.0, "wheels opposite: spin in place"
    assert icc_radius(5.0, 5.0, 20.0) is None, "straight: no centre"


def test_ensure_w_keeps_w_and_gives_up_v():
    """Notes §9 (Vmax 30, L 20, Wmax_V0 3, Vmax_W0 30): V 15, W 2 gives Vl_d -5, Vr_d 35,
    shifted by 5 to Vl -10, Vr 30: W stays 2 rad/s, V drops to 10."""
    vl, vr = ensure_w(15.0, 2.0, 20.0, 30.0, 30.0, 3.0)
    assert (vl, vr) == (-10.0, 30.0)
    assert diff_to_uni(vl, vr, 20.0) == (10.0, 2.0)


def test_ensure_w_clamps_w_and_v_first_and_shifts_up_for_fast_reverse():
    assert ensure_w(15.0, 9.0, 20.0, 30.0, 30.0, 3.0) == (-30.0, 30.0), "W held to 3: spin in place"
    vl, vr = ensure_w(-25.0, 1.0, 20.0, 30.0, 30.0, 3.0)  # Vl_d -35: lifted to -30
    assert (vl, vr) == (-30.0, -10.0) and diff_to_uni(vl, vr, 20.0)[1] == 1.0
    assert ensure_w(10.0, 0.5, 20.0, 30.0, 30.0, 3.0) == (5.0, 15.0), "within limits: unchanged"


def test_arduino_map_truncates_like_long_arithmetic_and_does_not_clamp():
    assert arduino_map(ROBOT_MIN_SPEED, ROBOT_MIN_SPEED, ROBOT_MAX_SPEED, PWM_MIN, PWM_MAX) == PWM_MIN
    assert arduino_map(ROBOT_MAX_SPEED, ROBOT_MIN_SPEED, ROBOT_MAX_SPEED, PWM_MIN, PWM_MAX) == PWM_MAX
    assert arduino_map(15.9, 8, 30, 107, 228) == arduino_map(15, 8, 30, 107, 228) == 107 + 7 * 121 // 22
    assert arduino_map(-10.0, 8, 30, 107, 228) == 107 - (18 * 121) // 22, "C division truncates towards 0"
    assert arduino_map(45.0, 8, 30, 107, 228) > 255, "no clamping"


def test_wheel_pwm_holds_map_to_the_analogwrite_range_forward_only():
    """The motors only run FORWARD: 0 cm/s maps to 63, where the motor stalls (chassis.py),
    a backward speed to less (the wheel stands), and under -11 cm/s map() goes negative,
    held at 0; over 255 is held at 255."""
    assert wheel_pwm(0.0) == 63
    assert wheel_pwm(-10.0) == 8
    assert wheel_pwm(-12.0) == 0 and wheel_pwm(-30.0) == 0
    assert wheel_pwm(60.0) == PWM_FULL
