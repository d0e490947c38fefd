"""What the firmware believed against the truth: telemetry lines read back from a
console, and the pool cleaner's panels from a hand-made trace folder."""

import json

import numpy as np
import pytest

from host.artefacts.folder import TraceData
from host.report import telemetry, viewkit
from sim_plant import catalogue
from sim_plant.catalogue import pool_lane as beliefs

POOL = {"name": "pool 25 x 8 m", "segments": [[0, 0, 25, 0], [25, 0, 25, 8], [25, 8, 0, 8], [0, 8, 0, 0]]}
HALF_W_M = 0.24


def test_telemetry_lines_are_read_by_their_tag_whatever_precedes_it_and_short_lines_are_skipped():
    text = (
        "pool cleaner on esp32 control every 50 ms\n"
        "lane 1000 0 7.51 7.500 -0.0100 7.500 0\n"
        "[   2.000100] lane 2000 1 -1.00 7.480 0.0020 7.500 -150\n"  # a time stamp before the tag
        "lane columns: t_ms sonar depth_m d_m phi_rad ref_m stop_ms\n"
        "lane 3000 0 7.5\n"  # cut short at the end of a run
        "cross 2: lane 7.10 m, sonar 0, t 0:01:27\n"
    )
    rows = telemetry.rows(text, "lane", beliefs.LANE_COLUMNS)
    assert rows["t_ms"].tolist() == [1000, 2000], rows
    assert rows["stop_ms"].tolist() == [0, -150] and rows["depth_m"].tolist() == [7.51, -1.0], rows
    empty = telemetry.rows("nothing here\n", "lane", beliefs.LANE_COLUMNS)
    assert all(len(v) == 0 for v in empty.values()) and set(empty) == set(beliefs.LANE_COLUMNS)


def pool_trace(tmp_path, console: str, events, truth, app="pool_cleaner_adc") -> TraceData:
    (tmp_path / "console.log").write_text(console)
    signals = {
        "probe:control": {"role": "probe", "kind": "level"},
        "sonar_l.adc": {"role": "sensor", "kind": "u16"},
        "sonar_r.adc": {"role": "sensor", "kind": "u16"},
        "track_l.stop": {"role": "actuator", "kind": "level"},
        "track_r.stop": {"role": "actuator", "kind": "level"},
    }
    header = {"app": app, "world": POOL, "signals": signals, "initial": {}, "t_end_us": 4_000_000}
    columns = {k: np.asarray(v, dtype=np.int64 if k == "t_us" else float) for k, v in truth.items()}
    return TraceData(tmp_path, json.loads(json.dumps(header)), list(events), columns, [])


def test_pool_cleaner_panels_put_the_kalman_estimate_beside_the_true_lane_and_explain_a_flat_adc_input(tmp_path):
    t0_us = 200_000  # the firmware's loop starts 0.2 s into the run: its t_ms counts from there
    console = "lane 1000 0 7.40 7.300 0.0000 7.500 -150\nlane 2000 0 7.50 7.400 0.0000 7.500 0\n"
    events = [(t0_us, "probe:control", 1)]
    events += [(500_000, "sonar_l.adc", 48_000), (1_000_000, "sonar_l.adc", 47_000)]
    events += [(t, "sonar_r.adc", 0) for t in (500_000, 1_000_000)]
    events += [(1_200_000, "track_l.stop", 1), (1_350_000, "track_l.stop", 0)]
    y_m = 8.0 - HALF_W_M - 7.45  # true d = 7.45 m all along
    truth = {
        "t_us": [0, 1_000_000, 2_000_000, 3_000_000],
        "y_m": [y_m] * 4,
        "sonar_l_range_m": [7.45] * 4,
        "sonar_r_range_m": [0.1, 0.2, 0.3, 0.3],
    }
    panels = {
        p.title.split(":")[0]: p
        for p in beliefs.pool_cleaner_view(viewkit, pool_trace(tmp_path, console, events, truth))
    }
    assert list(panels) == [
        "Side sonar",
        "ADC sonar inputs in metres",
        "Lane",
        "Lane error",
        "Track stops the firmware drove (steering)",
    ]

    firmware = next(line for line in panels["Lane"].lines if line.label.startswith("Kalman"))
    assert firmware.t_s == pytest.approx([1.2, 2.2]) and firmware.values == pytest.approx([7.3, 7.4])
    true_d = next(line for line in panels["Lane"].lines if line.label.startswith("true d"))
    assert true_d.values == pytest.approx([7.45] * 4)
    errors = {line.label.split(":")[0]: line.values for line in panels["Lane error"].lines}
    assert errors["estimate error"] == pytest.approx([-0.15, -0.05]), errors
    assert errors["lane error"] == pytest.approx([-0.05, -0.05]), errors

    adc = panels["ADC sonar inputs in metres"]
    left = next(line for line in adc.lines if line.label.startswith("sonar_l.adc"))
    assert left.values == pytest.approx([n * 3.3 / 65535 / 0.33 for n in (48_000, 47_000)])  # the firmware's law
    assert len(adc.notes) == 1 and adc.notes[0].startswith("sonar_r.adc stays at 0.00 V"), adc.notes
    assert "0.10-0.30 m away" in adc.notes[0] and "never selected sonar 1" in adc.notes[0], adc.notes

    stops = {line.label: line for line in panels["Track stops the firmware drove (steering)"].lines}
    assert stops["track_l.stop"].values.tolist() == [1, 0] and stops["track_l.stop"].t_s == pytest.approx([1.2, 1.35])


def test_a_pool_cleaner_that_printed_no_lane_lines_says_so_in_its_sonar_panel(tmp_path):
    truth = {"t_us": [0, 1_000_000], "y_m": [1.0, 1.0], "sonar_l_range_m": [7.0, 7.0]}
    view = catalogue.views()["pool_lane"]()  # (as a rig file's [report] views finds it)
    panels = view.panels(pool_trace(tmp_path, "pool cleaner on esp32\n", [], truth, app="pool_cleaner"), viewkit)
    assert any("no 'lane' lines in console.log" in note for note in panels[0].notes), panels[0].notes


def test_odometry_is_carried_into_the_worlds_frame_from_its_first_line_and_its_error_measured(tmp_path):
    """The lab robot's dead reckoning starts at (0, 0, 0) where the truth has it at
    (1, 2) heading +90 deg: 1 m forward by its count is 1 m up the world's y axis."""
    from host.report import odometry

    (tmp_path / "console.log").write_text(
        "pose columns: t_ms x_mm y_mm theta_rad\npose 0 0.0 0.0 0.0000\npose 1000 1000.0 0.0 0.0000\n"
    )
    pose_line = {"tag": "pose", "columns": ["t_ms", "x_mm", "y_mm", "theta_rad"], "m_per_unit": 0.001}
    pose_line |= {"rad_per_unit": 1.0, "probe": "probe:control", "what": "dead reckoning"}  # (its rig file's)
    header = {
        "app": "lab_robot",
        "initial": {},
        "t_end_us": 2_000_000,
        "signals": {},
        "report": {"pose_line": pose_line},
    }
    truth = {
        "t_us": np.asarray([0, 1_000_000, 2_000_000], dtype=np.int64),
        "x_m": np.asarray([1.0, 1.0, 1.0]),
        "y_m": np.asarray([2.0, 2.9, 3.8]),  # the truth went 0.9 m: the count says 1 m
        "theta_rad": np.asarray([np.pi / 2] * 3),
    }
    trace = TraceData(tmp_path, header, [(0, "probe:control", 1)], truth, [])
    path = odometry.belief_path(trace)
    assert path.x_m == pytest.approx([1.0, 1.0]) and path.y_m == pytest.approx([2.0, 3.0]), (path.x_m, path.y_m)
    assert np.degrees(path.theta_rad) == pytest.approx([90.0, 90.0])
    panels = {p.title.split(":")[0]: p for p in odometry.odometry_panels(trace)}
    error = dict((line.label, line.values) for line in panels["Dead reckoning error"].lines)
    assert error["position error (m)"] == pytest.approx([0.0, 0.1]), error
    assert panels["Dead reckoning error"].notes == ["at the end: 0.100 m and +0.0 deg off"]
    assert odometry.belief_path(TraceData(tmp_path, {**header, "report": None}, [], truth, [])) is None, "no pose line"
