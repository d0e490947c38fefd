"""The lab robot's algorithms against seed 004's numbers, on CPython and on MicroPython's
unix port (the board runs this code): Table 1 decoding, Eq. 1 odometry, the go-to action
of SquareBot with its v = sqrt(2 a d) profile, and Algorithm 3's wall-following law.
``lab_robot_checks.results()`` computes, the tests here compare with the seed."""

import json
import math
import subprocess

import pytest
from dead_reckoning import COUNTS_PER_REV, MU_RAD, TRACK_MM, WHEEL_RADIUS_MM
from host.core import interpreter
from host.core.paths import REPO
from lab_robot_checks import results
from quadrature import PHASE


def micropython_results() -> dict:
    path = ":".join(str(REPO / "firmware" / p) for p in ("apps/lab_robot", "tests")) + ":.frozen"
    script = "import json, lab_robot_checks\nprint(json.dumps(lab_robot_checks.results()))"
    out = subprocess.run(
        [str(interpreter.find()), "-c", script], env={"MICROPYPATH": path}, capture_output=True, text=True, timeout=60
    )
    assert out.returncode == 0, f"expected the checks to run on MicroPython, got:\n{out.stdout}{out.stderr}"
    return json.loads(out.stdout.strip().splitlines()[-1])


@pytest.fixture(scope="module", params=["cpython", "micropython"])
def got(request) -> dict:
    return results() if request.param == "cpython" else micropython_results()


def test_table_1_phases_are_gray_coded():
    """Seed 004 Table 1: AB = 00, 10, 11, 01 are phases 0, 1, 2, 3."""
    assert [PHASE[a * 2 + b] for a, b in ((0, 0), (1, 0), (1, 1), (0, 1))] == [0, 1, 2, 3]


def test_n_forward_phase_steps_decode_to_exactly_n_r_mu(got):
    """Eq. 4: S = R mu sum(+1): N steps forwards are N counts, N R mu of travel."""
    r_mu = WHEEL_RADIUS_MM * MU_RAD
    assert r_mu == pytest.approx(2 * math.pi * 35 / 80)  # 2.749 mm: R = 35 mm, 80 counts a turn
    for n in (1, 3, 4, 7, 80, 1001):
        count, errors, travel_mm = got["decoding"][f"forward_{n}"]
        assert (count, errors) == (n, 0), f"{n} steps forwards: expected {n} counts, no error; got {count}, {errors}"
        assert travel_mm == pytest.approx(n * r_mu, rel=1e-12), f"{n} steps: expected {n * r_mu} mm"
    assert got["decoding"]["forward_80"][2] == pytest.approx(2 * math.pi * WHEEL_RADIUS_MM)  # a wheel turn
    assert COUNTS_PER_REV == 80


def test_backward_steps_count_minus_one_and_a_two_phase_jump_is_an_error(got):
    """The reverse sequence counts -1 per step; a jump of two phases is counted as an
    error (and as two steps the way the wheel was turning); no new phase, no count."""
    for n in (1, 3, 4, 7, 80, 1001):
        assert got["decoding"][f"backward_{n}"] == [-n, 0]
    assert got["decoding"]["jump"] == [7, 1]  # 5 steps, then phase 1 -> 3
    assert got["decoding"]["repeat"] == [2, 0, 1]


def test_equal_wheel_increments_keep_the_heading(got):
    """Eq. 1: S_R = S_L turns nothing; the robot moves along its heading (Eq. 2)."""
    theta, x, y, v, w = got["odometry"]["straight"]
    assert theta == 0.3 and w == 0.0
    assert (x, y) == pytest.approx((250 * math.cos(0.3), 250 * math.sin(0.3)), rel=1e-12)
    assert v == pytest.approx(2.5 * 1000 / 50)


def test_s_r_minus_s_l_of_w_pi_over_2_turns_plus_90_degrees(got):
    """Eq. 1: theta = (S_R - S_L) / w; w pi / 2 more on the right wheel is a quarter turn
    to the left (counter-clockwise), on the spot or while driving."""
    theta, x, y = got["odometry"]["turn_one_step"]
    assert theta == pytest.approx(math.pi / 2, abs=1e-12) and (x, y) == (0.0, 0.0)
    theta, s_l, s_r = got["odometry"]["turn_driving"]
    assert theta == pytest.approx(math.pi / 2, abs=1e-12)
    assert s_r - s_l == pytest.approx(TRACK_MM * math.pi / 2)


def test_speed_is_the_finite_difference_from_zero(got):
    """Eq. 5 with S(-dt) = 0: the first step's speed is its travel over dt."""
    v, w = got["odometry"]["first_speed"]
    assert v == pytest.approx(40.0 / 0.05) and w == pytest.approx(20.0 / TRACK_MM / 0.05)


def test_deceleration_profile_gives_the_seed_speeds(got):
    """SquareBot: vel = sqrt(dist * 200 * 2): 894 mm/s at 2000 mm, 200 at 100, 63 at 10."""
    at_2000, at_100, at_10 = got["goto"]["profile"]
    assert round(at_2000) == 894 and at_100 == pytest.approx(200.0) and round(at_10) == 63
    assert at_2000 == pytest.approx(math.sqrt(800_000)) and at_10 == pytest.approx(math.sqrt(4000))


def test_goto_drives_ahead_capped_and_stops_within_the_close_distance(got):
    """Goal ahead: no turn, the profile capped at 400 mm/s, achieved within 10 mm and
    stopped; on the ideal profile the 2 m take sqrt(2 D / a) = 4.47 s plus the cap's
    extra (1 s at 400 mm/s) and the last steps."""
    run = got["goto"]["ahead"]
    assert run["achieved"] and run["dist_mm"] < 10.0
    assert run["max_v"] == 400.0 and abs(run["theta_deg"]) < 1e-9
    assert 5.0 <= run["steps"] * 0.05 <= 7.0, run


def test_goto_rotates_before_it_drives(got):
    """Goal to the left: rotate first, no translation while rotating, then drive."""
    run = got["goto"]["left"]
    assert run["achieved"] and run["dist_mm"] < 10.0
    assert run["max_v_while_rotating"] == 0.0, run
    assert run["theta_deg"] == pytest.approx(90.0, abs=1.0)


def test_a_close_distance_of_zero_is_refused(got):
    """Regression guard: the seed's setCloseDist(0) makes dist < closeDist impossible, so
    the goal is never achieved and SquareBot's busy-wait never ends; the firmware refuses it."""
    assert "never holds" in got["goto"]["close_zero"], got["goto"]["close_zero"]


def test_the_seed_s_counters_give_the_square_s_waypoints(got):
    """ps = {0, 2000, 2000, 0} walked by two 2-bit counters from x = 1, y = 0."""
    assert got["goto"]["waypoints"] == [[2000, 0], [2000, 2000], [0, 2000], [0, 0]]


def test_wall_bearing_by_triangulation_and_algorithm_3_gain(got):
    """The wall through the two left echoes: a parallel wall 400 mm away is abeam at
    400 mm; turned 10 degrees its nearest point is at 100 degrees. Algorithm 3: 0.125 deg/s
    per degree off abeam (left: theta - 90, right: theta + 90), none in the 1 degree band."""
    assert got["wall"]["parallel"] == pytest.approx([400.0, 90.0])
    assert got["wall"]["turned"] == pytest.approx([400.0, 100.0])
    assert got["wall"]["rotation"] == pytest.approx([1.25, 0.0, -0.25, -1.25, 1.25, -1.25])
