"""What the plots show, computed from a trace folder: plain numbers, no drawing.

- :func:`coverage` rasterises the ground-truth path into the world's coverage grid.
- :func:`signal_panels` picks the signals over time: a robot built from parts gets each
  part's declared views (:mod:`host.report.part_views`); a rig file adds views of its
  firmware's beliefs by name (``[report] views``, ``VIEWS`` below) and its odometry
  (``[report.pose_line]``); a plant of another kind without views gets the generic view
  (raw sensors, truth, actuators).
"""

import math
from dataclasses import dataclass

import numpy as np

from host.artefacts.folder import TraceData
from host.artefacts.recorder import ROLE_ACTUATOR, ROLE_SENSOR
from host.report import beliefs, odometry, part_views
from host.report.panels import US_PER_S, Line, Panel
from sim_plant.coverage import CoverageGrid
from sim_plant.world import World

COVERAGE_CELL_M = 0.05
__all__ = ["Line", "Panel", "US_PER_S", "coverage", "signal_panels", "belief_path"]
belief_path = odometry.belief_path  # the firmware's own idea of its path, for the trajectory


@dataclass
class Coverage:
    fraction: float
    covered: np.ndarray  # bool [ny, nx], free floor swept
    free: np.ndarray  # bool [ny, nx]
    extent: tuple[float, float, float, float]  # x0, x1, y0, y1 in metres


def world_of(trace: TraceData) -> World | None:
    world = trace.header.get("world")
    if not world or not world.get("segments"):
        return None
    return World(world["segments"], name=world.get("name", "world"))


def coverage(trace: TraceData, cell_m: float | None = None) -> Coverage | None:
    """Floor swept by the footprint along the ground-truth path, on a grid like the
    plant's own (None without a world)."""
    world = world_of(trace)
    x, y = trace.truth.get("x_m"), trace.truth.get("y_m")
    if world is None or x is None or y is None:
        return None
    cell_m = cell_m or trace.header.get("coverage_cell_m") or COVERAGE_CELL_M
    grid = CoverageGrid(world, cell_m, trace.header.get("footprint_half_width_m", 0.15))
    for xi, yi in zip(x, y):
        if math.isfinite(xi) and math.isfinite(yi):
            grid.add_point(float(xi), float(yi))
    fraction = grid.fraction()
    x0, y0 = grid.x0_m, grid.y0_m
    extent = (x0, x0 + grid.nx * grid.cell_m, y0, y0 + grid.ny * grid.cell_m)
    return Coverage(fraction, grid.covered & grid.free, grid.free, extent)


def range_ahead_m(x_m, y_m, theta_rad, segments, offset_m: float = 0.0) -> np.ndarray:
    """Distance along each heading to the nearest wall, less ``offset_m`` (the sensor
    sits on the body's edge): the true range a forward-looking sonar should report."""
    x, y = np.asarray(x_m, float)[:, None], np.asarray(y_m, float)[:, None]
    dx, dy = np.cos(theta_rad)[:, None], np.sin(theta_rad)[:, None]
    seg = np.asarray(segments, float)
    ax, ay, ux, uy = seg[:, 0], seg[:, 1], seg[:, 2] - seg[:, 0], seg[:, 3] - seg[:, 1]
    denom = dx * uy - dy * ux
    with np.errstate(divide="ignore", invalid="ignore"):
        t = ((ax - x) * uy - (ay - y) * ux) / denom
        s = ((ax - x) * dy - (ay - y) * dx) / denom
    hit = (np.abs(denom) > 1e-12) & (t > 0) & (s >= 0) & (s <= 1)
    dist = np.where(hit, t, np.inf).min(axis=1)
    return dist - offset_m


def bumps_s(trace: TraceData) -> np.ndarray:
    """Times the ground truth recorded a contact."""
    return np.asarray([c[0] / US_PER_S for c in trace.header.get("contacts", [])], dtype=float)


# -- signals over time ------------------------------------------------------------------


def signal_panels(trace: TraceData) -> list[Panel]:
    declared = (trace.header.get("report") or {}).get("views", [])
    panels = odometry.odometry_panels(trace)
    for name in declared:
        view = VIEWS.get(name)
        panels += view(trace) if view else [Panel(f"[report] views: no view {name!r}", "", notes=[", ".join(VIEWS)])]
    parts = part_views.part_panels(trace)
    if parts is not None:
        panels += parts
    elif not declared:
        panels += generic_view(trace)
    for panel in panels:  # an input never sampled in this run (the lab robot's sonars on the square) is left out
        panel.lines = [line for line in panel.lines if len(line.t_s)]
    return [p for p in panels if p.lines]


def generic_view(trace: TraceData) -> list[Panel]:
    sensors = Panel("Sensors as the firmware reads them", "counts")
    for name, info in trace.signals(ROLE_SENSOR).items():
        if info["kind"] == "u16":
            t, v = trace.series(name)
            sensors.lines.append(Line(name, t / US_PER_S, v, "points"))
    truth = Panel("Ground truth", "")
    for column in ("v_m_s", "sonar_range_m"):
        if column in trace.truth:
            truth.lines.append(Line(column, trace.truth["t_us"] / US_PER_S, trace.truth[column]))
    return [sensors, truth, actuator_panel(trace)]


def actuator_panel(trace: TraceData) -> Panel:
    panel = Panel("Actuator commands", "duty (fraction)")
    for name, info in trace.signals(ROLE_ACTUATOR).items():
        if info["kind"] == "duty":
            t, v = trace.series(name)
            panel.lines.append(Line(name, t / US_PER_S, v / 65535, "step"))
    return panel


# -- the rover (firmware/apps/rover) -----------------------------------------------------

ROVER_M_PER_VOLT = 512 * 0.0254 / 3.3  # firmware/lib/analog_sonar.py: Vcc/512 per inch
ROVER_VREF = 3.3
ROVER_M_PER_COUNT = 2 * math.pi * 0.033 / 40  # firmware/apps/rover/main.py: M_PER_COUNT


def rover_view(trace: TraceData) -> list[Panel]:
    sonar = Panel("Sonar: what the firmware read against the true range ahead", "range (m)")
    t, u16 = trace.series("sonar.adc")
    sonar.lines.append(
        Line(
            "sonar reading (ADC sample, firmware's law)",
            t / US_PER_S,
            u16 * ROVER_VREF / 65535 * ROVER_M_PER_VOLT,
            "points",
        )
    )
    tr = trace.truth
    segments = (trace.header.get("world") or {}).get("segments")
    if segments and "theta_rad" in tr:
        true_m = range_ahead_m(tr["x_m"], tr["y_m"], tr["theta_rad"], segments, trace.header["footprint_half_width_m"])
        sonar.lines.append(Line("true range ahead (ground truth)", tr["t_us"] / US_PER_S, true_m))

    speed = Panel("Speed: encoder estimate against the truth", "speed (m/s)")
    steps_t, est = rover_speed_estimate(trace)
    speed.lines.append(Line("estimate: encoder counts per control step", steps_t / US_PER_S, est, "step"))
    if "v_m_s" in tr:
        speed.lines.append(Line("true speed (ground truth)", tr["t_us"] / US_PER_S, tr["v_m_s"]))

    commands = Panel("Motor commands (signed duty)", "duty (-1 .. 1)")
    for side in ("l", "r"):
        t_s, duty = signed_duty(trace, f"motor_{side}")
        commands.lines.append(Line(f"motor_{side}", t_s, duty, "step"))
    return [sonar, speed, commands]


def rover_speed_estimate(trace: TraceData) -> tuple[np.ndarray, np.ndarray]:
    """Mean wheel speed over each control step from the encoder edges, counted as the
    firmware counts them (both edges of A, direction from B; firmware/lib/encoder.py)."""
    t_probe, level = trace.series("probe:control")
    changed = np.concatenate([[True], level[1:] != level[:-1]]) if len(level) else np.zeros(0, dtype=bool)
    steps = np.unique(t_probe[changed])  # a control step starts at each toggle
    if len(steps) < 2:
        return np.zeros(0), np.zeros(0)
    speeds = []
    for a_name, b_name in (("enc_l.a", "enc_l.b"), ("enc_r.a", "enc_r.b")):
        level_b = trace.header["initial"].get(b_name, 0)
        times, counts = [], []
        for t, name, value in trace.events:
            if name == b_name:
                level_b = value
            elif name == a_name:
                times.append(t)
                counts.append(1 if value != level_b else -1)
        idx = np.searchsorted(np.asarray(times, dtype=np.int64), steps, side="right")
        cum = np.concatenate([[0], np.cumsum(counts)])
        speeds.append(np.diff(cum[idx]) * ROVER_M_PER_COUNT / (np.diff(steps) / US_PER_S))
    return steps[1:], (speeds[0] + speeds[1]) / 2


def signed_duty(trace: TraceData, motor: str) -> tuple[np.ndarray, np.ndarray]:
    """Duty with the direction the H-bridge pins give it (IN1 - IN2), as a step series."""
    level = {"in1": 0, "in2": 0, "pwm": 0}
    names = {f"{motor}.{k}": k for k in level}
    t_out, v_out = [], []
    for t, name, value in trace.events:
        key = names.get(name)
        if key is None:
            continue
        level[key] = value
        t_out.append(t / US_PER_S)
        v_out.append((level["in1"] - level["in2"]) * level["pwm"] / 65535)
    return np.asarray(t_out), np.asarray(v_out)


VIEWS = {"rover": rover_view, "pool_lane": beliefs.pool_cleaner_view}
"""Views a rig file names in ``[report] views``: what its firmware believes, rebuilt from
its signals and telemetry lines by the firmware's own laws."""
