"""What the plots show, from hand-made traces: coverage of the floor, the true range
ahead, the encoder speed estimate, the signed motor commands, and the progress line."""

import math
from pathlib import Path

import numpy as np
import pytest

from host.artefacts.folder import TraceData
from host.report import views
from host.report.progress import MissionProgress

ROOM = {"name": "room 5 x 4 m", "segments": [[0, 0, 5, 0], [5, 0, 5, 4], [5, 4, 0, 4], [0, 4, 0, 0]]}


def trace_of(events=(), truth=None, **header) -> TraceData:
    h = {"app": "rover", "world": ROOM, "footprint_half_width_m": 0.17, "initial": {}, "t_end_us": 10_000_000}
    h.update(header)
    columns = {k: np.asarray(v, dtype=np.int64 if k == "t_us" else float) for k, v in (truth or {}).items()}
    return TraceData(Path("."), h, list(events), columns, [])


def test_a_straight_drive_covers_a_strip_as_wide_as_the_footprint():
    x = np.linspace(1.0, 4.0, 61)  # 3 m along y = 2 m, footprint 0.4 m wide (8 cells of 5 cm)
    truth = {"t_us": np.arange(61) * 50_000, "x_m": x, "y_m": np.full(61, 2.0)}
    cov = views.coverage(trace_of(truth=truth, footprint_half_width_m=0.2))
    expected = (3.0 * 0.4 + math.pi * 0.2**2) / (5 * 4)  # a 3 m x 0.4 m strip with round ends
    assert cov.fraction == pytest.approx(expected, rel=0.05), (cov.fraction, expected)
    assert cov.extent == (0.0, 5.0, 0.0, 4.0)
    assert cov.free.all(), "every cell of an empty room is floor"
    rows = np.flatnonzero(cov.covered.any(axis=1)) * 0.05 + 0.025
    assert rows.min() == pytest.approx(1.825) and rows.max() == pytest.approx(2.175), rows


def test_true_range_ahead_is_the_distance_to_the_wall_in_front_less_the_body():
    r = views.range_ahead_m(
        [1.0, 1.0, 2.5], [2.0, 2.0, 1.0], np.array([0.0, math.pi / 2, -math.pi / 2]), ROOM["segments"], 0.17
    )
    assert r == pytest.approx([5.0 - 1.0 - 0.17, 4.0 - 2.0 - 0.17, 1.0 - 0.17])


def test_motor_command_is_the_duty_signed_by_the_h_bridge_pins():
    events = [
        (0, "motor_l.in1", 1),
        (0, "motor_l.pwm", 32768),
        (100, "motor_l.in1", 0),
        (100, "motor_l.in2", 1),
        (200, "motor_l.pwm", 65535),
    ]
    t_s, duty = views.signed_duty(trace_of(events), "motor_l")
    assert duty[-1] == -1.0 and duty[1] == pytest.approx(32768 / 65535)
    assert list(t_s) == [0, 0, 1e-4, 1e-4, 2e-4]


def test_progress_stays_quiet_for_short_runs_and_shows_simulated_against_mission_time():
    now = [100.0]
    shown = []
    progress = MissionProgress("pool", rewrite=shown.append, clock=lambda: now[0])
    progress(0, 3_600_000_000)
    now[0] += 0.5
    progress(30_000_000, 3_600_000_000)
    assert shown == [], "a run shorter than a second shows nothing"
    now[0] += 1.5
    progress(120_000_000, 3_600_000_000)
    assert shown == ["pool: 120.0 / 3600.0 s simulated (3%), 2.0 s wall, 60x real time, about 58 s left"], shown
    assert progress.shown


def test_progress_in_a_log_writes_a_line_now_and_then_and_at_the_end():
    now = [0.0]
    lines = []
    progress = MissionProgress("pool", line=lines.append, clock=lambda: now[0])
    for step in range(1, 41):  # 40 s of wall time, a report every second
        progress((step - 1) * 90_000_000, 3_600_000_000)
        now[0] += 1.0
    progress(3_600_000_000, 3_600_000_000)
    assert len(lines) == 3 and lines[-1].startswith("pool: 3600.0 / 3600.0 s simulated (100%)"), lines
    quiet = MissionProgress("short", line=lines.append, clock=lambda: now[0])
    quiet(0, 10_000_000)
    now[0] += 2.0
    quiet(10_000_000, 10_000_000)
    assert len(lines) == 3, "a mission shorter than a log interval writes nothing to a log"


def test_the_terminal_summary_is_a_line_a_scenario_in_100_columns_naming_the_worst_budget():
    from host.report.table import format_summary
    from host.rig.config.verdicts import judged

    long = "test_" + "long_name_" * 8
    keys = ("scenario", "budget", "limit", "count", "p50", "max", "misses", "checked")
    rows = [
        dict(zip(keys, (long, "control.period", "50000 +- 1000 us", 600, 50000, 52000, 3, "missed"))),
        dict(zip(keys, (long, "sonar.period", "500000 +- 1000 us", 60, 500000, 500000, 0, "held"))),
    ]
    rows = judged(rows, test_failed=True)
    rows += judged(
        [dict(zip(keys, ("test_quiet", "control.compute", "<= 50000 us wall", 10, 9, 90000, 4, None)))], False
    )
    text = format_summary(rows, {long})
    lines = text.splitlines()
    assert max(map(len, lines)) <= 100, max(map(len, lines))
    assert lines[0].startswith("Budgets MISSED: 1 missed"), lines[0]
    assert lines[2] == long and "MISSED control.period 3/600, max 52000" in lines[3], "a long name: a line of its own"
    assert lines[4].startswith("test_quiet") and "all 0 held" in lines[4], "wall-clock budgets are informational"
    assert "sonar.period" in text and text.count("test_quiet") == 1, "the table: only scenarios that missed"


def test_a_mission_becomes_a_moving_picture_with_the_robot_where_the_truth_puts_it(tmp_path):
    from PIL import Image

    from host.report.movie import write_movie

    t = np.arange(0, 30_000_001, 1_000_000)
    truth = {"t_us": t, "x_m": t / 1e7, "y_m": np.zeros(len(t)), "theta_rad": np.zeros(len(t))}
    trace = TraceData(folder=tmp_path, header={"app": "rover", "seed": 1, "t_end_us": int(t[-1])}, truth=truth)
    path = write_movie(trace, tmp_path / "trajectory.gif", frames=5)
    gif = Image.open(path)
    assert gif.n_frames == 5 and gif.size[0] >= 300, (gif.n_frames, gif.size)
    first, last = np.asarray(gif.convert("RGB")), None
    gif.seek(4)
    last = np.asarray(gif.convert("RGB"))
    green = lambda img: np.argwhere((img[..., 1] > 100) & (img[..., 0] < 80) & (img[..., 2] < 80))  # noqa: E731
    assert green(last)[:, 1].mean() > green(first)[:, 1].mean() + 50, "the robot moves right across the frames"
