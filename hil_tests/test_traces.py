"""A recorded rover run leaves a complete, reproducible trace folder; a replay of it
drives the firmware with the recorded sensors and finds the first changed output; its
plots have content."""

import csv
import json
import re

import numpy as np
import pytest
from matplotlib.image import imread

from host.artefacts.console import stamped_lines
from host.artefacts.folder import load_trace, reseal
from host.report.plots import plot_trace
from host.rig.loop.replay import replay
from host.tests.vcd_reader import gtkwave_round_trip, read_vcd

pytestmark = [pytest.mark.hil, pytest.mark.xdist_group("test_traces")]  # (make hil: its module fixtures run once)

DURATION_S = 12


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    """One 12 s rover run that bumps into the wall, recorded (shared by the tests that read it)."""
    from host.rig import Recording, Rig, RigSpec

    folder = tmp_path_factory.mktemp("rover-seed11")
    spec = RigSpec("rover", seed=11, options={"room_w_m": 3.5})
    with Rig(spec, Recording(trace=True, record=True, artefacts=folder)) as rig:
        rig.run_for(DURATION_S)
    return folder, rig


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def test_a_recorded_run_leaves_header_signals_truth_budgets_link_and_vcd(recorded):
    folder, rig = recorded
    where = f"(artefacts: {folder})"
    header = json.loads((folder / "header.json").read_text())
    assert header["app"] == "rover" and header["board"] == "esp32_devkitc" and header["seed"] == 11, where
    assert header["world"]["name"] == "room 3.5 x 4 m" and header["plant_options"] == {"room_w_m": 3.5}, where
    assert re.fullmatch(r"[0-9a-f]{40}(-dirty)?", header["commit"]), f"commit {header['commit']!r} {where}"
    assert header["micropython"] == "1.25.0", where
    assert header["t_end_us"] == DURATION_S * 1_000_000, where

    signals = rows(folder / "signals.csv")
    samples = [r for r in signals if r["signal"] == "sonar.adc"]
    steps = [r for r in signals if r["signal"] == "probe:control"]
    assert len(samples) == rig.budgets["sonar.period"].stats()["count"] + 1, f"one row per sonar sample {where}"
    assert len(steps) >= rig.budgets["control.period"].stats()["count"] + 1, where
    assert {"motor_l.pwm", "motor_r.pwm", "enc_l.a", "enc_r.b", "bumper.out"} <= {r["signal"] for r in signals}, where
    t = [int(r["t_us"]) for r in signals]
    assert t == sorted(t), f"signals.csv is not in time order {where}"

    truth = rows(folder / "truth.csv")
    t_truth = [int(r["t_us"]) for r in truth]
    assert t_truth[0] == 0 and t_truth[-1] > (DURATION_S - 0.1) * 1e6, where
    assert max(np.diff(t_truth)) <= 70_000, f"truth every 50 ms (chunks of 20 ms), got gaps of {max(np.diff(t_truth))}"
    assert float(truth[-1]["x_m"]) == pytest.approx(rig.truth()["x_m"], abs=0.05), where

    budgets = {b["name"]: b for b in json.loads((folder / "budgets.json").read_text())}
    period = rig.budgets["control.period"]
    assert budgets["control.period"]["histogram_us"] == [list(kv) for kv in sorted(period.histogram.items())], where
    assert budgets["control.period"]["stats"] == period.stats(), where
    assert budgets["sonar.latency"]["stats"]["misses"] == 0, where

    link = [json.loads(line) for line in (folder / "trace.jsonl").read_text().splitlines()]
    assert link[0]["header"]["seed"] == 11 and any(m.get("msg") == "STATE" for m in link), where

    vcd = read_vcd((folder / "trace.vcd").read_text())
    last_pwm = int([r for r in signals if r["signal"] == "motor_l.pwm"][-1]["value"])
    assert vcd.final("rover.actuators.motor_l.pwm") == last_pwm, where
    assert len(vcd.timeline("rover.sensors.sonar.adc")) == len({r["t_us"] for r in samples}) + 1, where
    assert vcd.final("rover.truth.x_m") == pytest.approx(float(truth[-1]["x_m"]), rel=1e-6), where

    # the console's lines carry their virtual time, in console.log and as the VCD's events
    console = list(stamped_lines(folder / "console.log"))
    assert vcd.timeline("rover.events.console") == console, where
    bumped = min(int(r["t_us"]) for r in signals if r["signal"] == "bumper.out" and r["value"] == "0")
    backup = [t for t, line in console if line.startswith("rover: backup")]
    assert backup and 0 <= backup[0] - bumped <= 50_000, (
        f"expected the backup line within one 50 ms control period of the bump at {bumped} us, got {backup} {where}"
    )
    gtkw = (folder / "trace.gtkw").read_text().splitlines()
    assert set(vcd.vars) == {line for line in gtkw if line.startswith("rover.")}, f"trace.gtkw shows it all {where}"


def test_gtkwave_reads_the_recorded_vcd_back_unchanged(recorded, tmp_path):
    folder, _ = recorded
    ours = read_vcd((folder / "trace.vcd").read_text())
    theirs = read_vcd(gtkwave_round_trip(folder / "trace.vcd", tmp_path))
    assert set(theirs.vars) == set(ours.vars) and len(ours.vars) > 20, sorted(ours.vars)
    changed = [name for name in ours.vars if theirs.timeline(name) != ours.timeline(name)]
    assert not changed, f"GTKWave reads {changed} differently from {folder / 'trace.vcd'}"


def test_the_same_seed_gives_byte_identical_signals_truth_and_vcd(make_rig):
    folders = []
    for _ in range(2):
        rig = make_rig("rover", seed=12, record=True, trace=True)
        rig.run_for(5)
        rig.stop()
        folders.append(rig.artefacts)
    for name in ("signals.csv", "truth.csv", "trace.vcd", "trace.jsonl", "console.log", "trace.gtkw"):
        a, b = (f / name for f in folders)
        assert a.read_bytes() == b.read_bytes(), f"{name} differs between {a} and {b}"
    headers = [json.loads((f / "header.json").read_text()) for f in folders]
    for header in headers:  # (the seal of budgets.json, whose wall-clock figures differ run to run)
        del header["files"]["budgets.json"], header["digest"]
    assert headers[0] == headers[1], f"header.json differs beyond budgets.json's seal between {folders}"


def test_replaying_a_recording_gives_the_same_firmware_outputs(recorded, tmp_path):
    folder, _ = recorded
    result = replay(folder, tmp_path / "replay")
    assert result.same, f"{result.difference} (artefacts: {folder}, replay: {result.folder})"
    assert result.recorded == result.replayed > 400, result


def test_replay_finds_where_a_changed_sonar_reading_changes_the_motor_commands(recorded, tmp_path):
    folder, _ = recorded
    copy = tmp_path / "edited"
    copy.mkdir()
    for f in ("header.json", "signals.csv", "truth.csv", "budgets.json"):
        (copy / f).write_bytes((folder / f).read_bytes())
    signals = (copy / "signals.csv").read_text().splitlines()
    target = next(i for i, line in enumerate(signals) if ",sonar.adc," in line and int(line.split(",")[0]) > 2_000_000)
    t_sample = int(signals[target].split(",")[0])
    signals[target] = f"{t_sample},sonar.adc,{1 << 10}"  # 0.25 m: a wall appears to be close
    (copy / "signals.csv").write_text("\n".join(signals) + "\n")
    reseal(copy)  # (an edit on purpose: else the digests refuse the folder)

    result = replay(copy, tmp_path / "replay")
    diff = result.difference
    assert diff is not None, "a near wall in the sonar stream should change what the firmware drives"
    assert t_sample <= diff.t_us <= t_sample + 100_000, f"{diff}; sample edited at t={t_sample} us"
    assert diff.recorded[1] in ("motor_l.pwm", "motor_r.pwm", "motor_l.in1", "motor_r.in1"), diff


def test_replay_points_at_a_recorded_output_that_was_changed(recorded, tmp_path):
    folder, _ = recorded
    copy = tmp_path / "edited"
    copy.mkdir()
    for f in ("header.json", "truth.csv", "budgets.json"):
        (copy / f).write_bytes((folder / f).read_bytes())
    data = load_trace(folder)
    outputs = data.firmware_outputs()
    t, name, value = outputs[300]
    lines = (folder / "signals.csv").read_text().splitlines()
    index = lines.index(f"{t},{name},{value}")
    lines[index] = f"{t},{name},{value + 1}"
    (copy / "signals.csv").write_text("\n".join(lines) + "\n")
    reseal(copy)
    result = replay(copy, tmp_path / "replay")
    assert result.difference is not None and result.difference.index == 300, result.difference
    assert result.difference.recorded == (t, name, value + 1) and result.difference.replayed == (t, name, value)


def colours(png) -> int:
    rgb = (png[..., :3] * 255).round().astype(np.uint32).reshape(-1, 3)
    return len(np.unique(rgb @ np.array([1 << 16, 1 << 8, 1], dtype=np.uint32)))


def has_colour(png, rgb, tol=8) -> int:
    """Pixels within ``tol`` (0..255) of an RGB colour."""
    diff = np.abs(png[..., :3] * 255 - np.asarray(rgb)).max(axis=-1)
    return int((diff <= tol).sum())


def test_plots_show_the_path_the_signals_and_the_budgets(recorded, tmp_path):
    folder, _ = recorded
    written = {p.stem: p for p in plot_trace(folder, tmp_path)}
    assert set(written) == {"trajectory", "signals", "timing"}, written
    for path in written.values():
        png = imread(path)
        assert png.shape[0] > 400 and png.shape[1] > 600, f"{path}: {png.shape}"
        assert png[..., :3].std() > 0.05 and colours(png) > 50, f"{path} looks blank: {colours(png)} colours"
    trajectory, timing = imread(written["trajectory"]), imread(written["timing"])
    assert has_colour(trajectory, (140, 204, 140)) > 500, "no covered floor drawn in the trajectory plot"
    assert has_colour(trajectory, (38, 50, 56)) > 500, "no walls drawn in the trajectory plot"
    assert has_colour(timing, (77, 144, 81)) > 100, "no green (held) histogram bars in the timing plot"
    assert has_colour(trajectory, (198, 40, 40), tol=30) > 20, "the bump is not marked on the trajectory"
