"""Dead-reckoning lab robot firmware in the loop (seed 004): the 2 m square by go-to goals
on quadrature odometry (SquareBot), left-wall following through the S-curve canyon
(SCurveBot, with SonarBot's polling), and the timing the encoders and sonars need.

Figures from the seed's programs: the square's waypoints (2000, 0), (2000, 2000), (0, 2000),
(0, 0) mm with three +90 degree turns, ending at -90 degrees; the go-to profile
sqrt(2 x 200 mm/s^2 x d); the wall-follow gain 0.125 deg/s per degree at 400 mm/s; sonar
reads from 1000 ms on, every 100 ms. Each scenario records its result for ``make hil``
(``record_property("result", ...)``); docs/lab_robot.md has the measured figures.
"""

import math
import re
import statistics
from pathlib import Path

import pytest

from host.core.paths import REPO
from host.rig.config.apps import get_app
from host.rig.config.budgets import CHANGE, Budget
from sim_plant.catalogue.assembly import rig_plant_table
from sim_plant.world import CANYON_END_M

pytestmark = pytest.mark.hil

BOARDS = ("esp32_lab_robot", "rpi_pico_lab_robot")
CLOSE_TOLERANCE_MM = 20.0
ENCODERS = re.compile(
    r"encoders: left (-?\d+) counts (\d+) errors (\d+) idle, right (-?\d+) counts (\d+) errors (\d+) idle"
)
POSE = re.compile(r"at (\d+) ms: x (-?[0-9.]+) mm y (-?[0-9.]+) mm theta (-?[0-9.]+) deg")
NOISE_SEEDS = range(1, 21)
MAKE_TEST_SEEDS = 5  # (make test's share of the sweep; make hil runs every seed)
NOISY_MEAN_LIMIT_MM = 100.0  # 1.25 % of the 8 m path
NOISY_MAX_LIMIT_MM = 200.0  # 2.5 %
EDGE_HANDLER_US = 200  # what the firmware's IRQ handler may take on a board (docs/lab_robot.md)
MM_PER_COUNT = 2 * math.pi * 35.0 / 80  # the plant's wheel (r = 35 mm) and 80 counts a turn
TRACK_M = 0.2
BODY_RADIUS_M = rig_plant_table(Path(REPO, "firmware", "apps", "lab_robot", "rig-canyon.toml"))["body_radius_m"]


def run_until_console(rig, text, limit_s, step_s=0.5):
    """Run until the firmware prints ``text``, for at most ``limit_s`` more simulated s."""
    deadline_us = rig.t_us + limit_s * 1e6
    while text not in rig.console and rig.t_us < deadline_us:
        rig.run_for(step_s)
    assert text in rig.console, (
        f"expected {text!r} within {limit_s:g} simulated s, got none by t = {rig.t_us / 1e6:.1f} s; "
        f"console tail:\n{rig.console[-1500:]}\nartefacts: {rig.artefacts}"
    )


def encoders(rig) -> dict:
    """What the firmware's decoders counted: {side: (count, errors, idle)}."""
    m = ENCODERS.search(rig.console)
    assert m, f"expected the firmware's encoder report; console:\n{rig.console[-1500:]}\nartefacts: {rig.artefacts}"
    v = [int(g) for g in m.groups()]
    return {"l": tuple(v[:3]), "r": tuple(v[3:])}


def firmware_pose(rig, what) -> tuple[float, float, float]:
    """The firmware's own estimate (x_mm, y_mm, theta_deg) on the line that starts with ``what``."""
    line = next(line for line in rig.console.splitlines() if line.startswith(what))
    m = POSE.search(line)
    return float(m.group(2)), float(m.group(3)), float(m.group(4))


def closing_error_mm(rig) -> float:
    x0, y0, _ = rig.plant.start_pose
    truth = rig.truth()
    return math.hypot(truth["x_m"] - x0, truth["y_m"] - y0) * 1000


def check_every_edge_decoded(rig, missed=(0, 0)):
    """The firmware's counts are the plant's edges, each missed edge one error."""
    truth, got = rig.truth(), encoders(rig)
    for i, side in enumerate("lr"):
        count, errors, idle = got[side]
        expected = (truth[f"enc_{side}_edges"], missed[i], missed[i])
        assert (count, errors, idle) == expected, (
            f"{side} encoder: expected (counts, errors, idle handlers) {expected} as the plant made them, "
            f"got {(count, errors, idle)}; artefacts: {rig.artefacts}"
        )


def legs_and_turns(truth_rows):
    """From ground truth sampled every 50 ms: each driving leg (a run of samples with the
    robot going forwards faster than 50 mm/s) as (heading_deg, length_m, max |w| rad/s),
    and the turn made between two legs (deg)."""
    legs, turns, leg, turn_rad, prev = [], [], None, 0.0, None
    for _t, row in truth_rows:
        th = row["theta_rad"]
        if prev is not None and leg is None:
            turn_rad += math.remainder(th - prev, 2 * math.pi)
        if row["v_m_s"] > 0.05:
            if leg is None:
                leg = [row]
                if legs:
                    turns.append(math.degrees(turn_rad))
            else:
                leg.append(row)
        elif leg is not None:
            legs.append(_leg(leg))
            leg, turn_rad = None, 0.0
        prev = th
    if leg is not None:
        legs.append(_leg(leg))
    return legs, turns


def _leg(rows):
    sin_sum, cos_sum = sum(math.sin(r["theta_rad"]) for r in rows), sum(math.cos(r["theta_rad"]) for r in rows)
    heading = math.degrees(math.atan2(sin_sum, cos_sum))
    length = math.hypot(rows[-1]["x_m"] - rows[0]["x_m"], rows[-1]["y_m"] - rows[0]["y_m"])
    return heading, length, max(abs(r["w_rad_s"]) for r in rows)


def angle_off_deg(a, b):
    return abs(math.degrees(math.remainder(math.radians(a - b), 2 * math.pi)))


@pytest.mark.parametrize("board", BOARDS)
def test_square_closes_within_20mm_after_three_left_turns_facing_minus_90(make_rig, record_property, board):
    """SquareBot with perfect encoders: (2000, 0), (2000, 2000), (0, 2000), (0, 0) mm, turning
    on the spot before each leg (no translation while rotating), back at the start within
    20 mm, facing -90 degrees; every encoder edge decoded, the control step every 50 ms."""
    rig = make_rig("lab_robot", board=board, seed=1, record=True)
    run_until_console(rig, "square done", 60)
    error_mm, theta_deg = closing_error_mm(rig), math.degrees(rig.truth()["theta_rad"])
    legs, turns = legs_and_turns(rig.recorder.truth)
    headings = [round(h, 1) for h, _length, _w in legs]
    est = firmware_pose(rig, "square done")
    record_property(
        "result",
        f"{board}: square closed {error_mm:.1f} mm from the start, final heading {theta_deg:.2f} deg, "
        f"turns {', '.join(f'{t:+.1f}' for t in turns)} deg, legs at {headings} deg; firmware's estimate "
        f"({est[0]:.1f}, {est[1]:.1f}) mm; {rig.t_us / 1e6:.1f} s",
    )
    where = f"artefacts: {rig.artefacts}"
    assert error_mm <= CLOSE_TOLERANCE_MM, f"expected the square closed within 20 mm, got {error_mm:.1f} mm; {where}"
    assert angle_off_deg(theta_deg, -90) < 2.0, f"expected a final heading of -90 deg, got {theta_deg:.2f}; {where}"
    assert len(legs) == 4, f"expected 4 legs (rotate, then drive), got {len(legs)}: {legs}; {where}"
    for (heading, length_m, w_max), expected in zip(legs, (0, 90, 180, -90)):
        assert angle_off_deg(heading, expected) < 2.0 and abs(length_m - 2.0) < 0.05, (
            f"expected a 2 m leg at {expected} deg, got {length_m:.3f} m at {heading:.1f} deg; {where}"
        )
        assert w_max < 0.2, f"expected only steering corrections while driving, got {w_max:.2f} rad/s; {where}"
    assert turns == pytest.approx([90.0, 90.0, 90.0], abs=2.0), f"expected three +90 deg turns, got {turns}; {where}"
    spinning = [row for _t, row in rig.recorder.truth if abs(row["w_rad_s"]) > 0.5]
    assert len(spinning) > 30 and max(abs(row["v_m_s"]) for row in spinning) < 0.03, (
        f"expected the turns made on the spot (no translation while rotating), got speeds up to "
        f"{max(abs(row['v_m_s']) for row in spinning):.3f} m/s while turning; {where}"
    )
    assert math.hypot(est[0], est[1]) < 10.0, f"expected the firmware's estimate within its 10 mm close distance: {est}"
    check_every_edge_decoded(rig)
    rig.budgets["control.period"].check()


def test_decoding_errors_match_the_missed_edges_the_plant_injected(make_rig, record_property):
    """Edges two at a time (missed_edge_p = 2 %): the firmware counts one decoding error per
    missed edge, as many as the plant injected on each wheel, and still counts every edge
    (a jump is two steps the way the wheel turns), so the square still closes."""
    rig = make_rig("lab_robot", seed=3, plant_options={"enc_l.missed_edge_p": 0.02, "enc_r.missed_edge_p": 0.02})
    run_until_console(rig, "square done", 60)
    truth = rig.truth()
    missed = (truth["enc_l_missed"], truth["enc_r_missed"])
    got = encoders(rig)
    error_mm = closing_error_mm(rig)
    record_property(
        "result",
        f"missed edges injected L {missed[0]}, R {missed[1]}; decoding errors counted L {got['l'][1]}, "
        f"R {got['r'][1]}; square closed {error_mm:.1f} mm from the start",
    )
    assert min(missed) >= 20, f"expected the plant to inject missed edges on both wheels, got {missed}"
    check_every_edge_decoded(rig, missed)
    assert error_mm <= CLOSE_TOLERANCE_MM, f"expected the square closed within 20 mm, got {error_mm:.1f} mm"


@pytest.mark.long
def test_square_closing_error_over_20_seeds_with_slip_and_missed_edges(make_rig, record_property, request):
    """The world "arena-noisy": each wheel slips by N(0, 1 %) of its travel, redrawn every
    100 ms, and 0.5 % of the edges come two at once. Dead reckoning cannot see slip: the
    firmware believes it is home each time, the plant says how far off it is. Over seeds
    1-20 the closing error is reported (mean, max) and bounded (mean <= 100 mm, max <= 200 mm:
    1.25 % and 2.5 % of the 8 m path). The 20 runs are neither recorded nor budgeted (the
    square scenarios above are); the worst one is run again, recorded, for the report.
    ``make test`` runs the first 5 seeds against the same bounds (``make hil``, all 20)."""
    noisy = get_app("lab_robot").worlds["arena-noisy"]
    seeds = NOISE_SEEDS if request.config.getoption("--hil-report") else NOISE_SEEDS[:MAKE_TEST_SEEDS]

    def square(seed, **kwargs):
        rig = make_rig("lab_robot", seed=seed, plant_options=noisy, **kwargs)
        run_until_console(rig, "square done", 60, step_s=2.0)
        truth = rig.truth()
        check_every_edge_decoded(rig, (truth["enc_l_missed"], truth["enc_r_missed"]))
        rig.stop()
        return rig, closing_error_mm(rig), math.hypot(*firmware_pose(rig, "square done")[:2])

    runs = [square(seed, record=False, trace=False, budgets=[])[1:] for seed in seeds]
    errors_mm = [error for error, _believed in runs]
    believed_mm = [believed for _error, believed in runs]
    mean_mm, max_mm = statistics.mean(errors_mm), max(errors_mm)
    worst = seeds[errors_mm.index(max_mm)]
    replay, replay_mm, _ = square(worst, record=True)
    record_property(
        "result",
        f"{len(seeds)} seeds, slip 1 %, 0.5 % missed edges: closing error mean {mean_mm:.1f} mm, sd "
        f"{statistics.stdev(errors_mm):.1f} mm, max {max_mm:.1f} mm (seed {worst}: mpy-fil run "
        f"firmware/apps/lab_robot/rig.toml --world arena-noisy --seed {worst} --duration 30); the firmware "
        f"believed itself within {max(believed_mm):.1f} mm of the start each time",
    )
    shown = ", ".join(f"{e:.0f}" for e in errors_mm)
    assert replay_mm == max_mm, f"expected seed {worst} to give the same run again, got {replay_mm} mm, not {max_mm}"
    replay.budgets["control.period"].check()
    assert max(believed_mm) < 10.0, f"expected the firmware to believe it closed the square each time: {believed_mm}"
    assert mean_mm <= NOISY_MEAN_LIMIT_MM and max_mm <= NOISY_MAX_LIMIT_MM, (
        f"expected a closing error of mean <= {NOISY_MEAN_LIMIT_MM:g} mm and max <= {NOISY_MAX_LIMIT_MM:g} mm, "
        f"got mean {mean_mm:.1f}, max {max_mm:.1f} (seed {worst}); errors by seed: {shown}; "
        f"artefacts of seed {worst}: {replay.artefacts}"
    )
    assert mean_mm > CLOSE_TOLERANCE_MM, f"expected the slip to show in the closing error, got {shown}"


@pytest.mark.parametrize("board", BOARDS)
def test_wall_following_reaches_the_canyon_end_without_a_contact(make_rig, record_property, board):
    """SCurveBot: at 400 mm/s, turning at 0.125 deg/s per degree that the nearest wall is off
    abeam, the robot follows the left wall through the S (1.2 m sideways over 12 m) and stops
    where the wall ends (nowall), without touching either wall."""
    rig = make_rig("lab_robot_canyon", board=board, seed=1, record=True)
    run_until_console(rig, "nowall", 60, step_s=1.0)
    rig.run_for(1.0)
    truth = rig.truth()
    rows = [row for _t, row in rig.recorder.truth]
    world = rig.plant.world
    beside = [r for r in rows if r["x_m"] > 1.0]  # off the closed end: the side walls
    clearance_m = min(world.clearance(r["x_m"], r["y_m"])[0] for r in beside) - BODY_RADIUS_M
    nowall_s = int(re.search(r"nowall: canyon end at (\d+) ms", rig.console).group(1)) / 1000
    headings = [math.degrees(r["theta_rad"]) for r in rows]
    speeds = [r["v_m_s"] for r in rows if r["v_m_s"] > 0.2]
    record_property(
        "result",
        f"{board}: no wall at {nowall_s:.2f} s, stopped at x = {truth['x_m']:.2f} m (walls end at "
        f"{CANYON_END_M:g} m); {len(truth['contacts'])} contacts, side walls at least {clearance_m * 1000:.0f} mm "
        f"off the body; heading {min(headings):+.1f} .. {max(headings):+.1f} deg; "
        f"mean speed {statistics.mean(speeds) * 1000:.0f} mm/s",
    )
    where = f"artefacts: {rig.artefacts}"
    assert truth["contacts"] == [], f"expected no wall touched, got {truth['contacts']}; {where}"
    assert CANYON_END_M - 0.2 <= truth["x_m"] <= CANYON_END_M + 0.5, (
        f"expected the robot to stop where the wall ends (x = {CANYON_END_M:g} m), "
        f"got x = {truth['x_m']:.2f} m; {where}"
    )
    assert truth["v_m_s"] == 0.0, f"expected the robot stopped at the canyon end, got {truth['v_m_s']} m/s; {where}"
    assert max(headings) > 5.0, f"expected the robot to turn through the S, got headings up to {max(headings):.1f}"
    assert clearance_m > 0.1, f"expected at least 0.1 m between the body and a side wall, got {clearance_m:.3f} m"
    assert statistics.mean(speeds) == pytest.approx(0.4, abs=0.01), f"expected 400 mm/s, got {statistics.mean(speeds)}"
    check_every_edge_decoded(rig)


class EdgeSpacingBudget(Budget):
    """The time an encoder's IRQ handler has: from each edge of the encoder to its next
    edge (either channel). A miss is an edge that follows the last one sooner than
    ``limit_us``, the handler's time on a board: it would find two edges, one missed."""

    def __init__(self, encoder: str, limit_us: int):
        super().__init__(
            f"{encoder}.edges",
            f"{encoder}.a",
            limit_us=limit_us,
            description=f"each {encoder} edge at least {limit_us} us before the next (the handler's time)",
        )
        self.encoder = encoder
        self._last_us = None

    def hooks(self) -> list[tuple]:
        return [(CHANGE, f"{self.encoder}.a", self.edge), (CHANGE, f"{self.encoder}.b", self.edge)]

    def edge(self, t_us: int, _value) -> None:
        if self._last_us is not None:
            gap = t_us - self._last_us
            self._record(gap, gap < self.limit_us)
        self._last_us = t_us

    def limit_text(self) -> str:
        return f">= {self.limit_us} us"


def test_timing_budgets_hold_at_400mm_s_control_sonar_and_every_encoder_edge(make_rig, record_property):
    """The canyon run at the firmware's top speed: a control step every 50 ms; SonarBot's
    polling, the first read at 1000 ms, then one every 100 ms, each reading read within one
    quantum of the sonar taking it; and every encoder edge handled before the next: at 400 mm/s an edge comes
    every 6.9 ms per wheel (146 edges/s; 182 edges/s at the motors' 500 mm/s), each at
    least the handler's 200 us after the last, and the decoders count exactly the plant's
    edges with no handler finding two (or none)."""
    app = get_app("lab_robot_canyon")
    plant = app.make_plant()
    edges = [EdgeSpacingBudget(enc, EDGE_HANDLER_US) for enc in ("enc_l", "enc_r")]
    rig = make_rig(app.name, seed=2, plant=plant, budgets=[*app.make_budgets(plant), *edges], record=True)
    run_until_console(rig, "nowall", 60, step_s=1.0)
    for budget in rig.budgets.values():
        if not budget.wall_clock:
            budget.check()
    check_every_edge_decoded(rig)
    events = rig.recorder.events
    start_us = next(t for t, name, _v in events if name.startswith("probe"))
    first_sample_us = next(t for t, name, _v in events if name == "sonar_l.adc") - start_us
    first_read_us = first_sample_us + rig.budgets["sonar.latency"].values[0]
    period, latency = rig.budgets["sonar.period"].stats(), rig.budgets["sonar.latency"].stats()
    control = rig.budgets["control.period"].stats()
    gap_us = min(min(b.values) for b in edges)
    n_edges = sum(len(b.values) + 1 for b in edges)
    v_max_mm_s = max(r["v_m_s"] + abs(r["w_rad_s"]) * TRACK_M / 2 for _t, r in rig.recorder.truth) * 1000
    record_property(
        "result",
        f"{control['count']} control steps {control['p50']}-{control['max']} us apart; first sonar read at "
        f"{first_read_us / 1000:g} ms, {period['count']} readings {period['max']} us apart, read "
        f"{latency['max']} us after at worst; {n_edges} encoder edges, the closest two of one encoder "
        f"{gap_us} us apart (top wheel speed {v_max_mm_s:.0f} mm/s), none missed",
    )
    assert first_sample_us == 999_000 and first_read_us == 1_000_000, (
        f"expected the first reading taken 999 ms after start (ranging from 950 ms) and read at 1000 ms, got "
        f"{first_sample_us} us and {first_read_us} us"
    )
    assert period["count"] >= 350 and period["max"] == 100_000, period
    assert latency["max"] <= 50_000 and control["max"] == 50_000, (latency, control)
    expected_gap_us = MM_PER_COUNT / v_max_mm_s * 1e6  # one count at the top wheel speed
    assert gap_us >= 0.9 * expected_gap_us and gap_us > 20 * EDGE_HANDLER_US, (
        f"expected edges of one encoder about {expected_gap_us:.0f} us apart at {v_max_mm_s:.0f} mm/s, "
        f"got {gap_us} us at the closest; artefacts: {rig.artefacts}"
    )
