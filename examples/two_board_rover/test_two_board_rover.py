"""two_board_rover in the loop: two boards' firmware, unchanged, on one simulated robot and
one virtual clock (docs/multi-board.md). The rig file beside it says which board drives
what and how the boards are wired to each other."""

import re
from pathlib import Path

import pytest

from host.rig.boardfile import load_boards
from host.rig.boardset import BoardSet

RIG = Path(__file__).parent / "rig.toml"
pytestmark = pytest.mark.hil


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """The rover for 10 s (the navigator commands for its first 8), kept for every test."""
    folder = tmp_path_factory.mktemp("two_board_rover")
    with BoardSet(load_boards(RIG), seed=1, artefacts=folder) as boards:
        boards.run_for(9.5)
        pose_9500ms = boards.truth()
        boards.run_for(0.5)
        yield boards, pose_9500ms, folder


def test_drives_and_turns_away_from_the_box_on_the_navigators_commands(run):
    boards, _, folder = run
    truth = boards.truth()
    assert truth["contacts"] == [], f"expected no contact, touched at {truth['contacts'][:3]} (artefacts: {folder})"
    assert truth["distance_m"] > 1.5, f"expected over 1.5 m driven, got {truth['distance_m']:.2f} m ({folder})"
    assert boards["nav"].console.count("turning") >= 1, boards["nav"].console
    assert "bad command" not in boards["motor"].console, boards["motor"].console


def test_the_motor_board_holds_the_commanded_speed_within_10_percent(run):
    boards, _, folder = run
    counts = [tuple(map(int, m)) for m in re.findall(r"nav: odometry (-?\d+) (-?\d+)", boards["nav"].console)]
    ahead = [(b[0] - a[0], b[1] - a[1]) for a, b in zip(counts[10:30], counts[11:31])]  # 1 s to 3 s: ahead
    assert len(ahead) == 20, f"expected 20 odometry answers from 1 s to 3 s, got {len(ahead)} ({folder})"
    for left, right in ahead:
        assert 45 <= left <= 55 and 45 <= right <= 55, f"expected 50 +- 5 counts per 100 ms, got {ahead} ({folder})"


def test_the_motor_board_stops_once_the_navigator_stops_commanding(run):
    boards, pose_9500ms, folder = run
    assert "nav: done" in boards["nav"].console, boards["nav"].console
    assert "motor: no command for 500 ms, stopping" in boards["motor"].console, boards["motor"].console
    moved = abs(boards.truth()["distance_m"] - pose_9500ms["distance_m"])
    assert moved < 1e-6, f"expected the robot still from 9.5 s on, it went {moved:.4f} m (artefacts: {folder})"


def test_the_motor_boards_speed_loop_keeps_its_20ms_period(run):
    boards, _, _ = run
    loop = boards["motor"].budgets["speed_loop"]
    loop.check()
    assert loop.stats()["count"] >= 490, loop.stats()
