"""What the plots show, computed from a trace folder: plain numbers, no drawing.

- :func:`coverage` rasterises the ground-truth path into the world's coverage grid.
- :func:`floor_picture` reads the floor's picture back, where the world has one drawn.
- :func:`signal_panels` picks the signals over time: a robot built from parts gets each
  part's declared views (:mod:`host.report.part_views`); a rig file adds views of its
  firmware's beliefs by name (``[report] views``: the catalogue's report views, ours and a
  user's, drawn with :mod:`host.report.viewkit`) and its odometry
  (``[report.pose_line]``); a plant of another kind without views gets the generic view
  (raw sensors, truth, actuators).
"""

import math
from dataclasses import dataclass

import numpy as np
from PIL import Image

from host.artefacts.folder import TraceData
from host.artefacts.recorder import ROLE_ACTUATOR, ROLE_SENSOR
from host.report import odometry, part_views, viewkit
from host.report.panels import US_PER_S, Line, Panel
from sim_plant import catalogue
from sim_plant.catalogue.coverage import CoverageGrid  # (the part's grid, redrawn from a trace)
from sim_plant.world import World

COVERAGE_CELL_M = 0.05
__all__ = ["Line", "Panel", "US_PER_S", "coverage", "floor_picture", "signal_panels", "belief_path"]
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


@dataclass
class FloorPicture:
    gray: np.ndarray  # uint8 [rows from the top, columns]: 0 black, 255 white
    extent: tuple[float, float, float, float]  # x0, x1, y0, y1 in metres


def floor_picture(trace: TraceData) -> FloorPicture | None:
    """The floor's picture (``floor.png``: a ``line_course`` world's) and where it lies;
    None without one, or without one the folder's seal vouches for."""
    floor = (trace.header.get("world") or {}).get("floor")
    if not isinstance(floor, dict):
        return None
    path = trace.folder / str(floor.get("picture", ""))
    if path.name not in (trace.header.get("files") or {}) or not path.is_file():
        return None
    with Image.open(path) as picture:
        gray = np.asarray(picture.convert("L"))
    x0, x1, y0, y1 = (float(v) for v in floor["extent_m"])
    return FloorPicture(gray, (x0, x1, y0, y1))


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
        view = catalogue.resolve("views", name)
        known = catalogue.views() if view is None else {}
        panels += (
            view({}).panels(trace, viewkit)
            if view
            else [Panel(f"[report] views: no view {name!r}", "", notes=[", ".join(known)])]
        )
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
