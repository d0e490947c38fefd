"""Obstacle avoidance of seed 003 (§4.4): readings through T_s^r and T_r^o (with 1, not
the seed's 0, in the homogeneous coordinate), the strip the body sweeps, the heading of
u_ao for an obstacle ahead, to one side, or dead ahead with both sides free; the hard
switch between the behaviours and the goals in turn."""

import math

import pytest
from avoidance import CORRIDOR_HALF_CM, D_MAX_CM, SWEEP_DEG, Obstacles, frame, reading_to_world
from chassis import SENSOR_X_CM
from navigator import AVOID, DONE, GO_TO_GOAL, Navigator

DEG = math.pi / 180


def test_the_sweep_is_the_seeds_five_angles():
    """§3.3: "The servo moves to the specified angle(10, 45, 90, 135, 170)"."""
    assert SWEEP_DEG == (10, 45, 90, 135, 170)


@pytest.mark.parametrize(
    "servo_deg, expect",
    [
        (90, (100.0, 50.0 + SENSOR_X_CM + 30.0)),
        (170, (100.0 - 30.0 * math.cos(10 * DEG), 60.0 + 30.0 * math.sin(10 * DEG))),
    ],
)
def test_a_reading_lands_in_the_world_through_both_frames(servo_deg, expect):
    """Robot at (100, 50) facing +y: 90 deg looks ahead (+y), 170 deg 80 deg to the left (-x)."""
    assert reading_to_world((100.0, 50.0, 90 * DEG), servo_deg, 30.0) == pytest.approx(expect)


def test_with_the_seeds_homogeneous_0_the_translations_would_be_lost():
    point = (30.0, 0.0, 0.0)  # [d, 0, 0] as printed
    t = frame(100.0, 50.0, 0.0)
    assert tuple(r[0] * point[0] + r[1] * point[1] + r[2] * point[2] for r in t)[:2] == (30.0, 0.0)
    assert reading_to_world((100.0, 50.0, 0.0), 90, 30.0) == pytest.approx((140.0, 50.0))


def sweep(obstacles, pose, ranges):
    for i, d in enumerate(ranges):
        obstacles.add(i, d, pose)
    return obstacles


def test_an_echo_in_the_bodys_strip_blocks_the_way_one_beside_it_does_not():
    pose = (0.0, 0.0, 0.0)
    ahead = sweep(Obstacles(), pose, (None, None, 40.0, None, None))
    assert ahead.blocked_to(pose, (300.0, 0.0), 60.0)
    assert not ahead.blocked_to(pose, (30.0, 0.0), 60.0), "the goal is nearer than the echo"
    assert not ahead.blocked_to(pose, (0.0, 300.0), 60.0), "the way to a goal on the left is clear"
    beside = Obstacles()
    beside.add(4, 30.0, pose)  # 170 deg: 80 deg left, 30 cm: 29.5 cm off the strip's axis
    assert 29.0 > CORRIDOR_HALF_CM and not beside.blocked_to(pose, (300.0, 0.0), 60.0)


def test_a_box_dead_ahead_with_both_sides_free_is_passed_on_the_goals_side():
    pose = (0.0, 0.0, 0.0)
    for goal, side in (((300.0, 10.0), 1.0), ((300.0, -10.0), -1.0)):
        obstacles = sweep(Obstacles(), pose, (None, None, 40.0, None, None))
        phi = obstacles.heading(pose, goal)
        assert math.cos(phi) == pytest.approx(0.0, abs=0.05) and math.sin(phi) == pytest.approx(side), goal


def test_with_the_right_side_blocked_the_robot_turns_left_and_never_at_the_echo():
    pose = (0.0, 0.0, 0.0)
    obstacles = sweep(Obstacles(), pose, (35.0, 40.0, 60.0, None, None))
    phi = obstacles.heading(pose, (300.0, 0.0))
    assert 0.0 < phi < math.pi / 2 + 0.01
    n = obstacles.nearest_ahead(pose)
    assert math.cos(phi) * n[0] + math.sin(phi) * n[1] <= 1e-9, "no component towards the nearest echo"


def test_readings_beyond_d_max_count_as_free_at_d_max():
    pose = (0.0, 0.0, 0.0)
    far, none = Obstacles(), Obstacles()
    far.add(2, 250.0, pose)
    none.add(2, None, pose)
    assert far.latest[2] == none.latest[2] == pytest.approx((SENSOR_X_CM + D_MAX_CM, 0.0))
    assert far.count == 0 and none.count == 0, "nothing within 150 cm: nothing remembered"


class FixedController:
    """A heading controller that records its set-points."""

    def __init__(self):
        self.set_points = []
        self.resets = 0

    def step(self, phi_d, phi, v):
        self.set_points.append(phi_d)
        return 100, 100

    def reset(self):
        self.resets += 1


def test_the_switch_avoids_within_60cm_holds_its_heading_and_hands_back_when_the_way_is_clear():
    """Every 500 ms: go-to-goal gives way when an echo is in the strip to the goal within
    60 cm; avoidance keeps the heading it chose until the strip to the goal is clear for
    80 cm; each switch resets the controller (the listing's orphan reset)."""
    ctl = FixedController()
    nav = Navigator([(300.0, 0.0)], ctl)
    pose = (0.0, 0.0, 0.0)
    nav.obstacles.add(2, 70.0, pose)  # 80 cm ahead of the axle: not yet
    assert not nav.check(pose) and nav.mode == GO_TO_GOAL
    nav.control(pose)
    assert ctl.set_points[-1] == 0.0, "go-to-goal steers at the goal's bearing"
    pose = (25.0, 0.0, 0.0)  # 55 cm from the echo now
    assert nav.check(pose) and nav.mode == AVOID and ctl.resets == 1
    held = nav.phi_ao
    assert abs(abs(held) - math.pi / 2) < 0.05, "head-on: square to the echo"
    nav.obstacles.add(0, None, pose)
    nav.control(pose)
    nav.control((25.0, 10.0, held))
    assert ctl.set_points[-2:] == [held, held], "held while the robot turns"
    side = math.copysign(1.0, held)
    assert not nav.check((25.0, 20.0 * side, held)) and nav.mode == AVOID, "20 cm aside: the echo is in the strip"
    assert nav.check((25.0, 40.0 * side, held)) and nav.mode == GO_TO_GOAL and ctl.resets == 2, "40 cm: clear"


def test_goals_are_visited_in_turn_and_the_robot_stops_after_the_last():
    ctl = FixedController()
    nav = Navigator([(100.0, 0.0), (100.0, 100.0)], ctl)
    assert nav.control((97.0, 2.0, 0.0)) == (0, 0) and nav.goal == (100.0, 100.0) and ctl.resets == 1
    nav.control((97.0, 2.0, 0.0))
    assert ctl.set_points[-1] == pytest.approx(math.atan2(98.0, 3.0))
    assert nav.control((100.0, 96.0, 1.5)) == (0, 0) and nav.mode == DONE
    assert nav.control((0.0, 0.0, 0.0)) == (0, 0) and [i for i, _ in nav.reached] == [0, 1]
