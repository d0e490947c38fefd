"""two_board_rover in the loop: two boards' firmware, unchanged, on one simulated robot and
one virtual clock (docs/multi-board.md). The rig file beside it says which board drives
what and how the boards are wired to each other; ``make_boards`` starts them."""

import re

import pytest

pytestmark = pytest.mark.hil


def test_drives_and_turns_away_from_the_box_on_the_navigators_commands(make_boards):
    boards = make_boards("rig.toml", seed=1)
    boards.run_for(6)
    truth = boards.truth()
    assert truth["contacts"] == [], f"expected no contact, touched at {truth['contacts'][:3]} ({boards.artefacts})"
    driven_m = truth["distance_m"]
    assert driven_m > 1.5, f"expected over 1.5 m driven, got {driven_m:.2f} m ({boards.artefacts})"
    assert boards["nav"].console.count("turning") >= 1, boards["nav"].console
    assert "bad command" not in boards["motor"].console, boards["motor"].console


def test_the_motor_board_holds_the_commanded_speed_within_10_percent(make_boards):
    boards = make_boards("rig.toml", seed=2)
    boards.run_for(3.3)
    counts = [tuple(map(int, m)) for m in re.findall(r"nav: odometry (-?\d+) (-?\d+)", boards["nav"].console)]
    ahead = [(b[0] - a[0], b[1] - a[1]) for a, b in zip(counts[10:30], counts[11:31])]  # 1 s to 3 s: ahead
    assert len(ahead) == 20, f"expected 20 odometry answers from 1 s to 3 s, got {len(ahead)} ({boards.artefacts})"
    for left, right in ahead:
        held = 45 <= left <= 55 and 45 <= right <= 55
        assert held, f"expected 50 +- 5 counts per 100 ms, got {ahead} ({boards.artefacts})"


def test_the_motor_board_stops_once_the_navigator_stops_commanding(make_boards):
    boards = make_boards("rig.toml", seed=3)
    boards.run_for(6)  # (the navigator commands for its first 5 s)
    driven_m = boards.truth()["distance_m"]
    boards.run_for(0.5)
    assert "nav: done" in boards["nav"].console, boards["nav"].console
    assert "motor: no command for 500 ms, stopping" in boards["motor"].console, boards["motor"].console
    moved = abs(boards.truth()["distance_m"] - driven_m)
    assert moved < 1e-6, f"expected the robot still from 6 s on, it went {moved:.4f} m ({boards.artefacts})"


def test_the_motor_boards_speed_loop_keeps_its_20ms_period(make_boards):
    boards = make_boards("rig.toml", seed=4)
    boards.run_for(3)
    loop = boards["motor"].budgets["speed_loop"]
    loop.check()
    assert loop.stats()["count"] >= 145, loop.stats()
