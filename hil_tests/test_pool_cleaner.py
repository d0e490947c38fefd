"""Pool cleaner firmware in the loop (seeds 000/001): the WEDA B400 in its pool, steered
by stopping a track, a side sonar on NMEA (or the ADC option), bumpers at both ends.

Figures from the seeds: a lane regained within 30 sonar samples (4.5 m) from a 0.3 m
error (thesis §5.3.1), more than 96 % of the surface in the short-side test (§7.3.1), the
25 x 8 m pool cleaned in about an hour against an estimate of 55 minutes (§7.3.3).
Each scenario records its result for ``make hil`` (``record_property("result", ...)``).
"""

import re

import pytest

from sim_plant.physics.coverage import CoverageRecorder
from sim_plant.pool import BODY_LENGTH_M, BODY_WIDTH_M

pytestmark = pytest.mark.hil

HALF_W_M = BODY_WIDTH_M / 2  # the sonars sit on the sides of the 0.48 m body
END_STRIP_M = BODY_LENGTH_M / 2 - HALF_W_M  # 0.21 m at each end wall no swath can reach


def reference_distance_m(truth, pool_width_m=8.0):
    """True distance from the left sonar to the reference wall (y = width)."""
    return pool_width_m - truth["y_m"] - HALF_W_M


def console_number(rig, pattern):
    m = re.search(pattern, rig.console)
    assert m, f"expected the firmware to print {pattern!r}; console:\n{rig.console[-2000:]}\nartefacts: {rig.artefacts}"
    return m.group(1)


def run_until_console(rig, text, limit_s, step_s=10.0):
    """Run until the firmware prints ``text``, for at most ``limit_s`` more simulated s."""
    deadline_us = rig.t_us + limit_s * 1e6
    while text not in rig.console and rig.t_us < deadline_us:
        rig.run_for(step_s)
    assert text in rig.console, (
        f"expected {text!r} within {limit_s:g} simulated s, got none by "
        f"t = {rig.t_us / 1e6:.0f} s; console tail:\n{rig.console[-1500:]}\n"
        f"artefacts: {rig.artefacts}"
    )


def check_budgets(rig, names=("control.period", "sonar.period", "sonar.latency", "track.stop")):
    for name in names:
        rig.budgets[name].check()


def test_lane_error_below_10cm_within_30_sonar_samples_from_a_30cm_offset(make_rig, record_property):
    """The operator sets the machine down 0.3 m off the lane it measured (seed 000 §6.3);
    from the first closed-loop sample the error must fall under 0.1 m within 30 samples
    (4.5 m) and stay there until 2 m before the far wall."""
    rig = make_rig("pool_cleaner", seed=1)
    run_until_console(rig, "waiting for bumper1", 10, step_s=0.05)
    width_m = float(console_number(rig, r"width ([0-9.]+) m"))
    x, y, th = (rig.truth()[k] for k in ("x_m", "y_m", "theta_rad"))
    rig.plant.carry_to((x, y + 0.3, th))
    run_until_console(rig, "straight 1:", 5, step_s=0.05)
    rig.run_for(5.0)  # the reversal and leaving-the-wall windows: open loop
    errors, travel_m = [], []
    x0 = rig.truth()["x_m"]
    while rig.truth()["x_m"] > 2.0:
        rig.run_for(0.5)
        truth = rig.truth()
        errors.append(reference_distance_m(truth) - width_m)
        travel_m.append(x0 - truth["x_m"])
    settle = next((i for i in range(len(errors)) if all(abs(e) < 0.1 for e in errors[i:])), None)
    shown = ", ".join(f"{e:+.2f}" for e in errors[:40])
    record_property(
        "result",
        f"lane error {errors[0]:+.2f} m -> under 0.10 m after {settle} samples "
        f"({travel_m[settle]:.1f} m), max after {max(abs(e) for e in errors[settle:]):.3f} m"
        if settle is not None
        else "lane never regained",
    )
    # the reversal's heading kick moves the machine a few cm in the 5 s of open loop
    assert abs(abs(errors[0]) - 0.3) < 0.08, f"expected to start about 0.3 m off the lane, got {errors[0]:+.2f} m"
    assert settle is not None and settle <= 30, (
        f"expected |lane error| < 0.1 m from sample <= 30 to the end of the run, got {settle}; "
        f"errors: {shown}; artefacts: {rig.artefacts}"
    )
    check_budgets(rig)


def test_short_side_coverage_above_96_percent(make_rig, record_property):
    """Seed 000 §7.3.1: lanes along the 8 m side, starting 13.7 m from the wall, 16 lanes.
    Coverage of the floor between the first lane and the last lane whose straight run is
    done, less the 0.21 m strips at the end walls that the body keeps the swath from.
    (Over seeds 1-10 in the loop: 95.6-98.2 %, mean 96.9 %; lanes 0.4 m apart under a
    0.48 m swath leave 8 cm of overlap, so a few centimetres of lane error show.)"""
    length_m, width_m, start_d_m = 8.0, 25.0, 13.7
    y0 = width_m - HALF_W_M - start_d_m
    rig = make_rig(
        "pool_cleaner",
        seed=1,
        plant_options={"pool_length_m": length_m, "pool_width_m": width_m, "start_pose": (length_m - 0.46, y0, 0.0)},
    )
    run_until_console(rig, "cross 32:", 1200)  # sixteen straight runs done
    lanes = [float(v) for v in re.findall(r"cross \d+: lane ([0-9.]+) m", rig.console)]
    y_last = width_m - HALF_W_M - min(lanes)
    grid = rig.plant.part(CoverageRecorder).grid
    covered = grid.fraction_in(END_STRIP_M, length_m - END_STRIP_M, y0, y_last)
    repeats = rig.console.count("repeating")
    record_property(
        "result",
        f"short side: {covered:.1%} of {y_last - y0:.1f} x {length_m - 2 * END_STRIP_M:.2f} m "
        f"in {rig.t_us / 60e6:.1f} min, {repeats} lane(s) repeated",
    )
    assert y_last - y0 >= 4.0, f"expected at least 11 lanes (4 m) in 16 runs, got {y_last - y0:.2f} m"
    assert covered > 0.96, (
        f"expected more than 96 % of the swept band covered, got {covered:.1%}; artefacts: {rig.artefacts}"
    )
    check_budgets(rig)


def test_full_pool_cleaned_in_about_an_hour_with_95_percent_coverage(make_rig, record_property):
    """Seed 000 §7.3.3 / seed 001 §7: the 25 x 8 m pool from a corner, a sonar switch
    half way; the start-up estimate ~55 min, the real run ~60 min."""
    rig = make_rig("pool_cleaner", seed=1, mission_s=60 * 60)  # the progress line: percent of the hour
    run_until_console(rig, "done:", 75 * 60, step_s=60.0)
    m = re.search(r"done: pool cleaned in (\d+):(\d+):(\d+)", rig.console)
    done_s = int(m.group(1)) * 3600 + int(m.group(2)) * 60 + int(m.group(3))
    e = re.search(r"cleaning time (\d+):(\d+):(\d+)", rig.console)
    estimate_s = int(e.group(1)) * 3600 + int(e.group(2)) * 60 + int(e.group(3))
    coverage = rig.truth()["coverage_fraction"]
    off = estimate_s / done_s - 1
    record_property(
        "result",
        f"full pool: {coverage:.1%} covered in {done_s / 60:.1f} min, start-up estimate "
        f"{estimate_s / 60:.1f} min ({off:+.1%}), {rig.truth()['reversals']} reversals",
    )
    assert "sonar: switching to sonar 1" in rig.console, "expected the switch to the other sonar half way"
    assert coverage >= 0.95, f"expected >= 95 % of the floor covered, got {coverage:.1%}; artefacts: {rig.artefacts}"
    assert 55 * 60 <= done_s <= 60.5 * 60, f"expected about 55-60 min (seed 000 §7.3.3), got {done_s / 60:.1f} min"
    assert abs(off) <= 0.15, f"expected the estimate within 15 % of {done_s / 60:.1f} min, got {estimate_s / 60:.1f}"
    check_budgets(rig)


def test_sonar_samples_are_read_within_one_quantum_and_stops_fit_their_slot(make_rig, record_property):
    """Budgets over 5 minutes, with sentences that end between two control steps (the
    firmware joins a sentence read in two pieces): every 500 ms sentence read within
    50 ms, every 50 ms step on time, every track stop at most 300 ms."""
    rig = make_rig("pool_cleaner", seed=5, plant_options={"sonar.phase_us": 120_000})
    rig.run_for(300)
    check_budgets(rig)
    latency = rig.budgets["sonar.latency"].stats()
    stops = rig.budgets["track.stop"].stats()
    period = rig.budgets["control.period"].stats()
    record_property(
        "result",
        f"budgets: {latency['count']} sentences read {latency['max'] / 1000:.1f} ms after "
        f"their last byte at worst; {stops['count']} stops, longest "
        f"{stops['max'] / 1000:.0f} ms; {period['count']} steps, max period {period['max']} us",
    )
    assert latency["count"] >= 598 and latency["max"] > 30_000, latency  # split sentences wait a quantum
    # (on time to the microsecond, but for the step after the 129 bytes printed at 88.75 s: one
    # byte past the console UART's 128-byte FIFO at 115 200 baud blocks for 86 us, docs/shim.md)
    assert period["count"] >= 5999 and period["max"] <= 50_087, period
    assert stops["count"] > 50, f"expected the machine to steer, got {stops}"


@pytest.mark.parametrize("kind, window_s", [("wrong", (40.0, 50.0)), ("silent", (40.0, 60.0))])
def test_sonar_faults_do_not_drive_the_cleaner_into_a_wall(make_rig, record_property, kind, window_s):
    """A burst of wrong readings (seed 000 §3.4.4, §7.3.3) and a 20 s sonar dropout,
    mid-run, mid-pool: no side wall touched, the machine never a lane (0.4 m) off its
    lane, and back on it (0.15 m) 15 s after the fault. Blind, the firmware steers on its
    dead-reckoned estimate: 20 s (6 m) at a heading known to 0.05 rad is 0.3 m."""
    start_y = 2.5
    rig = make_rig(
        "pool_cleaner",
        seed=1,
        plant_options={"start_pose": (25.0 - 0.46, start_y, 0.0), "sonar.faults": [(*window_s, kind)]},
    )
    run_until_console(rig, "straight 1:", 10, step_s=0.5)
    width_m = float(console_number(rig, r"width ([0-9.]+) m"))
    worst_m, after = 0.0, []
    while "cross 2:" not in rig.console:
        rig.run_for(0.5)
        t_s, err = rig.t_us / 1e6, abs(reference_distance_m(rig.truth()) - width_m)
        if window_s[0] <= t_s:
            worst_m = max(worst_m, err)
        if t_s > window_s[1] + 15 and rig.truth()["x_m"] > 2.0:
            after.append(err)
    walls = [c for c in rig.truth()["contacts"] if c.part == "body"]
    record_property(
        "result",
        f"{kind} sonar {window_s[0]:g}-{window_s[1]:g} s: worst lane error {worst_m:.2f} m, "
        f"{max(after):.2f} m from 15 s after, {len(walls)} side-wall contacts",
    )
    assert not walls, f"expected no side wall touched, got {walls}; artefacts: {rig.artefacts}"
    assert worst_m < 0.4, f"expected the machine within a lane (0.4 m) of its lane, got {worst_m:.2f} m off"
    assert after and max(after) < 0.15 and sum(after) / len(after) < 0.1, (
        f"expected the lane regained from 15 s after the fault, got errors up to {max(after):.2f} m"
    )
    check_budgets(rig, ("control.period", "sonar.latency", "track.stop"))  # a dropout is a period miss


def test_adc_sonar_build_keeps_its_lanes(make_rig, record_property):
    """The same firmware with the board file of the ADC option: two analog inputs, no
    UART; it measures the width, runs its lanes and keeps its budgets."""
    rig = make_rig("pool_cleaner_adc", seed=1)
    run_until_console(rig, "straight 3:", 200)
    width_m = float(console_number(rig, r"width ([0-9.]+) m"))
    rig.run_for(30)
    lane_m = width_m - 0.4
    err = reference_distance_m(rig.truth()) - lane_m
    record_property("result", f"ADC sonar: width {width_m:.2f} m, second lane error {err:+.2f} m")
    assert abs(width_m - 7.5) < 0.1, f"expected the 7.5 m start-up width, got {width_m:.2f} m"
    assert abs(err) < 0.1, f"expected the second lane held within 0.1 m, got {err:+.2f} m; artefacts: {rig.artefacts}"
    check_budgets(rig)
