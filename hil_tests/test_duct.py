"""Seed 002's duct inspection robot in the loop (docs/duct.md): the Kp sweep of the integer
P speed loop at a 60-tick set-point, odometry on a straight 1 m duct, the single right
branch run (with and without tether snags), the recursive exploration of a multi-branch
duct, and the record stream to the master. Each scenario records its figures for
``make hil`` (``record_property("result", ...)``)."""

import math

import pytest

from sim_plant.duct_link import RecordReader
from sim_plant.tether import TetherSnag

pytestmark = pytest.mark.hil

SET_POINT = 60
SWEEP = (100, 40, 30, 25, 20, 10)  # Kp x 100
HOME_TOLERANCE_M = 0.15
START = (0.3, 0.2)
HIL_ONLY = pytest.mark.skipif("not config.getoption('--hil-report')", reason="make hil runs all 20 seeds")
BRANCH_SEEDS = [s if s == 1 else pytest.param(s, marks=HIL_ONLY) for s in range(1, 21)]


def where(rig) -> str:
    return f"seed {rig.seed}; console tail:\n{rig.console[-1200:]}\nartefacts: {rig.artefacts}"


def run_until(rig, text, limit_s, step_s=1.0):
    deadline_us = rig.t_us + limit_s * 1e6
    while text not in rig.console and rig.t_us < deadline_us:
        rig.run_for(step_s)
    return text in rig.console


def step_response(make_rig, kp100, seconds=3.0):
    """The master sets the gain and a 60-tick step on both wheels at 0; the records give
    each 50 ms period's slot counts."""
    script = [[0, f"K {kp100}"], [0, f"S {SET_POINT} {SET_POINT}"]]
    rig = make_rig("duct", seed=1, plant_options={"world": "bench", "link_options": {"script": script}})
    rig.run_for(seconds)
    reader = rig.plant.part(RecordReader)
    values = sorted(reader.values)
    start = next(i for i, v in enumerate(values) if v[1] or v[2])
    return rig, [v[1] for v in values[start:]], [v[2] for v in values[start:]]


def metrics(speeds):
    """(overshoot, sign changes of the error bigger than 3 ticks, first period within 3
    ticks, mean error over the last 10 periods, peak-to-peak over the last 20)."""
    errors = [SET_POINT - s for s in speeds]
    big = [e for e in errors if abs(e) > 3]
    changes = sum(1 for a, b in zip(big, big[1:]) if (a > 0) != (b > 0))
    rise = next((k for k, e in enumerate(errors) if abs(e) <= 3), len(errors))
    tail = speeds[-20:]
    return max(speeds) - SET_POINT, changes, rise, sum(errors[-10:]) / 10, max(tail) - min(tail)


def test_kp_sweep_at_a_60_tick_set_point(make_rig, record_property):
    """App. D.5: Kp = 1.0 oscillates without end, 0.4 swings past and back, 0.3 overshoots, 0.25 reaches 60 cleanly and
    fastest, 0.1 and 0.2 are slower, 0.1 with a large steady-state error; both wheels at
    0.25 within 2 ticks of each other every period."""
    results, wheels = {}, None
    for kp in SWEEP:
        rig, left, right = step_response(make_rig, kp)
        results[kp] = metrics(left)
        if kp == 25:
            wheels = max(abs(a - b) for a, b in zip(left, right))
            rig.budgets["control.period"].check()
        rig.stop()
    record_property(
        "result",
        "; ".join(
            f"Kp {kp / 100:g}: overshoot {m[0]}, oscillation sign changes {m[1]}, within 3 ticks at period {m[2]}, "
            f"final error {m[3]:.1f}, tail p-p {m[4]}"
            for kp, m in results.items()
        )
        + f"; Kp 0.25 wheels differ by at most {wheels} ticks",
    )
    msg = f"Kp sweep (overshoot, sign changes, rise, final error, tail p-p): {results}"
    assert results[100][4] >= 20 and results[100][1] >= 4, f"expected Kp = 1 to oscillate without end; {msg}"
    assert results[40][0] > 2 * results[30][0] and results[40][1] >= 1, (
        f"expected Kp = 0.4 to swing past the set-point and back, twice as far as 0.3 (in this plant it then "
        f"settles: the seed's sustained oscillation at 0.4 is not reproduced, docs/duct.md); {msg}"
    )
    assert results[30][0] > 3 and results[30][4] <= 4, f"expected Kp = 0.3 to overshoot, then settle; {msg}"
    assert results[25][0] <= 3 and results[25][1] == 0 and abs(results[25][3]) <= 3, (
        f"expected Kp = 0.25 to reach 60 without overshoot or oscillation, within 3 ticks; {msg}"
    )
    clean = [kp for kp in SWEEP if results[kp][0] <= 3 and results[kp][1] == 0]
    assert min(clean, key=lambda kp: (results[kp][2], -kp)) == 25, f"expected 0.25 the fastest clean gain; {msg}"
    assert results[20][2] > results[25][2] and results[10][2] > results[20][2], f"expected 0.2, 0.1 slower; {msg}"
    assert results[10][3] >= 4, f"expected Kp = 0.1 to keep a large steady-state error; {msg}"
    assert wheels <= 2, f"expected both wheels within 2 ticks at Kp = 0.25, got {wheels}"


STRAIGHT_STARTS = {1: (0.3, 0.2, 0.0), 2: (0.3, 0.16, 0.06), 3: (0.3, 0.24, -0.06)}
STRAIGHT_BOARDS = {1: "esp32_duct", 2: "rpi_pico_duct", 3: "esp32_duct"}  # the same firmware, both pin maps


@pytest.mark.parametrize("run", [1, 2, 3])
def test_straight_1m_duct_odometry_within_50mm(make_rig, record_property, run):
    """§5.4: three runs through a straight duct of about 1 m (started centred and square,
    then 40 mm off-centre and 3.4 degrees askew either way); at the duct end the firmware's
    odometry is within 50 mm of where the robot really is."""
    start = STRAIGHT_STARTS[run]
    options = {"world": "straight_1m", "start_pose": list(start)}
    rig = make_rig("duct", board=STRAIGHT_BOARDS[run], seed=run, plant_options=options)
    assert run_until(rig, "duct end", 20, 0.1), f"expected the duct end within 20 s; {where(rig)}"
    line = next(x for x in rig.console.splitlines() if x.startswith("duct end"))
    fx, fy = (float(v) for v in line.split("x ")[1].split(" mm y ")[0:1] + [line.split(" mm y ")[1].split(" mm")[0]])
    truth = rig.truth()
    dx, dy = truth["x_m"] - start[0], truth["y_m"] - start[1]  # in the robot's start frame, as its odometry
    c, s = math.cos(start[2]), math.sin(start[2])
    tx, ty = (c * dx + s * dy) * 1000, (-s * dx + c * dy) * 1000
    error = math.hypot(fx - tx, fy - ty)
    record_property(
        "result",
        f"run {run} ({STRAIGHT_BOARDS[run]}): travelled {math.hypot(tx, ty):.0f} mm, odometry error {error:.1f} mm",
    )
    pins = STRAIGHT_BOARDS[run].replace("_", "-")
    assert f"duct robot on {pins}:" in rig.console, f"expected the firmware on {pins}'s pin map; {where(rig)}"
    assert tx > 950, f"expected about 1 m travelled, got {tx:.0f} mm; {where(rig)}"
    assert error <= 50, (
        f"expected odometry within 50 mm, got {error:.1f} mm (({fx}, {fy}) vs ({tx:.0f}, {ty:.0f})); {where(rig)}"
    )


def branch_run(make_rig, seed, **options):
    """The single right branch run (§5.7): forward to the end, reverse, turn into the
    branch, explore it, reverse out, reverse home. Success: one branch, two ends, the list
    empty, and the robot really within 150 mm of its start."""
    rig = make_rig("duct", seed=seed, plant_options=options, record=False, trace=False)
    done = run_until(rig, "explored:", 90, 2.0)
    truth = rig.truth()
    off = math.hypot(truth["x_m"] - START[0], truth["y_m"] - START[1])
    ok = done and "explored: 1 branches found, 2 ends, 0 left" in rig.console and off <= HOME_TOLERANCE_M
    snags = rig.plant.part(TetherSnag).events if options.get("snag_p") else []
    return rig, ok, off, snags


@pytest.mark.parametrize("seed", BRANCH_SEEDS)
def test_single_right_branch_without_snags(make_rig, record_property, seed):
    """§5.7 without the tether catching: every run explores the branch and comes home; the
    speed loop runs every 50 ms and each sonar reading is read before the next."""
    rig, ok, off, _ = branch_run(make_rig, seed)
    record_property("result", f"seed {seed}: {'success' if ok else 'FAILED'}, {off * 1000:.0f} mm from the start")
    assert ok, f"expected the branch explored and home within 150 mm, got {off * 1000:.0f} mm off; {where(rig)}"
    for name in ("control.period", "sonar_f.latency", "sonar_l.latency", "sonar_r.latency", "link.latency"):
        rig.budgets[name].check()


SNAG_P = 0.12


def test_single_right_branch_with_tether_snags(make_rig, record_property, request):
    """§5.7: 18 of 20 runs succeeded, both failures from the tether catching. With snags
    at spins (p = 0.12 a spin, 4 spins a run) about 2 of 20 runs fail; every failure had a
    snag. make test runs seed 1 (one snag, recovered), make hil all 20."""
    seeds = range(1, 21) if request.config.getoption("--hil-report") else range(1, 2)
    outcomes = []
    for seed in seeds:
        rig, ok, off, snags = branch_run(make_rig, seed, snag_p=SNAG_P)
        outcomes.append((seed, ok, len(snags), off))
        rig.stop()
    wins = sum(ok for _s, ok, _n, _o in outcomes)
    record_property(
        "result",
        f"{wins} of {len(outcomes)} succeeded; runs with snags: "
        + ", ".join(
            f"seed {s} ({n} snag(s), {'ok' if ok else 'failed'}, {o * 1000:.0f} mm off)"
            for s, ok, n, o in outcomes
            if n
        ),
    )
    unexplained = [s for s, ok, n, _o in outcomes if not ok and n == 0]
    assert not unexplained, f"expected every failure traced to a snag; failed without one: seeds {unexplained}"
    if len(outcomes) == 20:
        assert 16 <= wins <= 19, f"expected about 18 of 20 successes, got {wins}: {outcomes}"


@pytest.mark.parametrize(
    "gains", [(1.0, 1.0), pytest.param((0.9, 1.0), marks=HIL_ONLY)], ids=["exact", "left-wheel-10pc-slow"]
)
def test_multi_branch_duct_explored_recursively(make_rig, record_property, gains):
    """§4.6: every branch explored (unexplored ones forwards, explored ones left in
    reverse), no spurious branch, the list empty, home reached; with a 10 % velocity
    error on one wheel the exploration still completes (home by the robot's own odometry;
    its true distance from the start is reported, not bounded)."""
    rig = make_rig("duct", seed=1, plant_options={"world": "multi_branch", "motor_gains": list(gains)}, record=False)
    done = run_until(rig, "explored:", 240, 5.0)
    truth = rig.truth()
    off = math.hypot(truth["x_m"] - START[0], truth["y_m"] - START[1])
    summary = next((x for x in rig.console.splitlines() if x.startswith("explored:")), "not finished")
    spins = rig.console.count("spin ")
    record_property(
        "result", f"gains {gains}: {summary}; {spins} spins; home {off * 1000:.0f} mm off; {rig.t_us / 1e6:.0f} s"
    )
    assert done, f"expected the exploration to finish within 240 s; {where(rig)}"
    assert "explored: 4 branches found, 5 ends, 0 left in the list" in summary, (
        f"expected 4 branches (no spurious one), 5 ends, the list empty; got {summary!r}; {where(rig)}"
    )
    assert spins == 8, f"expected 8 spins (into and out of each branch), got {spins}; {where(rig)}"
    if gains == (1.0, 1.0):  # with the 10 % error the firmware believes it is home, but is not (docs/duct.md)
        assert off <= HOME_TOLERANCE_M, f"expected home within 150 mm, got {off * 1000:.0f} mm; {where(rig)}"


def test_record_stream_none_lost_when_drained_fast_and_overrun_counted_when_not(make_rig, record_property):
    """§3.4: the master polls more often than records are made: every record arrives, in
    order, within one poll period and the batch's time on the line. A master that polls
    every 2.5 s lets the 32-record ring overwrite: the robot counts the overruns and the
    master sees exactly that many sequence numbers missing."""
    fast = make_rig("duct", seed=1, plant_options={"world": "bench", "link_options": {"poll_ms": 100}})
    fast.run_for(10.0)
    t = fast.truth()
    fast.budgets["control.period"].check()
    fast.budgets["link.latency"].check()
    made = round(fast.t_us / 50_000)
    fast.stop()
    slow = make_rig("duct", seed=1, plant_options={"world": "bench", "link_options": {"poll_ms": 2500}})
    slow.run_for(10.0)
    s = slow.truth()
    slow.stop()
    record_property(
        "result",
        f"poll 100 ms: {t['link_records']} records, {t['link_skipped']} lost, "
        f"latency spread {t['link_latency_max_us']} us; "
        f"poll 2500 ms: {s['link_records']} records, {s['link_skipped']} lost, robot's overruns {s['link_overruns']}",
    )
    assert t["link_skipped"] == 0 and t["link_overruns"] == 0 and t["link_bad_lines"] == 0, f"expected none lost: {t}"
    assert t["link_records"] >= made - 3, f"expected about {made} records, got {t['link_records']}: {t}"
    assert t["link_latency_max_us"] <= 100_000 + 10_000, f"expected latency within a poll and a batch: {t}"
    assert s["link_overruns"] > 0 and s["link_skipped"] == s["link_overruns"], f"expected overruns counted: {s}"


def first_spin_theta(rig) -> float:
    line = next(x for x in rig.console.splitlines() if x.startswith("spin right"))
    return float(line.split("theta ")[1].split(" deg")[0])


def test_spin_odometry_under_reports_without_the_90_degree_override(make_rig, record_property):
    """§5.7: in a spin the backward wheel is pushed without turning its encoder, so the
    odometry's turn is short of the true 90 degrees; the 90-degree override (option "O 1 0",
    the default) sets it to 90 exactly. Turned off ("O 0 0") the first right spin reads about
    (1 + 0.7) / 2 x 90 = 76 degrees."""
    thetas, truths = {}, {}
    for option in ("O 0 0", "O 1 0"):
        options = {"link_options": {"script": [[100, option]]}}
        rig = make_rig("duct", seed=1, plant_options=options, record=False, trace=False)
        assert run_until(rig, "spin right", 30, 0.5), f"expected a spin within 30 s; {where(rig)}"
        thetas[option], truths[option] = first_spin_theta(rig), math.degrees(rig.truth()["theta_rad"])
        rig.stop()
    record_property(
        "result",
        f"odometry heading after the first right spin: without the override {thetas['O 0 0']:.1f} deg "
        f"(true {truths['O 0 0']:.1f}), with it {thetas['O 1 0']:.1f} deg (true {truths['O 1 0']:.1f})",
    )
    assert -82 <= thetas["O 0 0"] <= -70, f"expected the odometry to see about 76 deg of the spin: {thetas}"
    assert abs(thetas["O 1 0"] + 90) <= 6, f"expected the override to give -90 deg within the pre-spin drift: {thetas}"
    for option, true in truths.items():
        assert abs(true + 90) <= 10, f"expected a true turn of about 90 deg ({option}): {truths}"


@HIL_ONLY
def test_positional_fix_still_explores_the_branch(make_rig, record_property):
    """§5.7's positional fix as an option ("O 1 1"): at each spin the position is set to the
    branch's stored spin point; the single right branch run still succeeds."""
    rig, ok, off, _ = branch_run(make_rig, 1, link_options={"script": [[100, "O 1 1"]]})
    record_property("result", f"positional fix: {'success' if ok else 'FAILED'}, {off * 1000:.0f} mm from the start")
    assert ok, f"expected the positional fix run to explore the branch and come home; {where(rig)}"


def test_e_stop_from_the_master_stops_the_robot_within_a_control_period(make_rig, record_property):
    """§3.4: the master's emergency stop ("E") mid-run: both wheels stop within one 50 ms
    speed-loop period of the robot reading the line, and stay stopped."""
    rig = make_rig("duct", seed=1, plant_options={"link_options": {"script": [[3000, "E"]]}})
    rig.run_for(3.0)
    moving = rig.truth()["v_m_s"]
    rig.run_for(0.07)  # the line read within 10 ms, the duty zeroed at the next period
    stopped = rig.truth()
    rig.run_for(1.0)
    later = rig.truth()
    record_property("result", f"e-stop at 3.0 s: {moving:.3f} m/s before, {stopped['v_m_s']:.3f} m/s 70 ms later")
    assert moving > 0.1, f"expected the robot under way at 3 s, got {moving:.3f} m/s; {where(rig)}"
    assert "e-stop at" in rig.console, f"expected the firmware to report the e-stop; {where(rig)}"
    assert stopped["v_m_s"] == 0 and later["v_m_s"] == 0 and later["x_m"] == stopped["x_m"], (
        f"expected the wheels stopped within 70 ms and still: {stopped['v_m_s']}, {later['v_m_s']}; {where(rig)}"
    )
