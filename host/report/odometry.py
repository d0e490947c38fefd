"""Where the firmware's odometry put the robot against where it was, from its telemetry
lines and the trace's truth. A rig file says how its firmware prints its pose
(``[report.pose_line]``, kept in the trace header): the vacuum's odometry prints
``pose t_ms x_cm y_cm phi_deg`` every 500 ms, the lab robot's dead reckoning
``pose t_ms x_mm y_mm theta_rad`` every 250 ms.

The odometry counts from its own origin; its first line, taken before the robot moves,
is matched to the true pose at that time, and every later pose is carried into the
world's frame by that rotation and offset.
"""

from dataclasses import dataclass

import numpy as np

from host.artefacts.folder import TraceData
from host.report import telemetry
from host.report.panels import US_PER_S, Line, Panel


@dataclass(frozen=True)
class PoseLine:
    """How an app prints its pose: the tag's columns, the metres per unit of x and y,
    the radians per unit of the heading, and the probe its loop starts with."""

    columns: tuple[str, str, str, str]
    m_per_unit: float
    rad_per_unit: float
    probe: str
    what: str  # what the firmware calls it
    tag: str = "pose"  # the telemetry line's tag


def pose_line(header: dict) -> PoseLine | None:
    """How the run's firmware prints its pose, as its rig file declared it (None: not)."""
    spec = (header.get("report") or {}).get("pose_line")
    if not spec:
        return None
    return PoseLine(
        tuple(spec["columns"]), spec["m_per_unit"], spec["rad_per_unit"], spec["probe"], spec["what"], spec["tag"]
    )


@dataclass
class BeliefPath:
    """The firmware's poses in the world's frame, with the true pose at the same times."""

    what: str
    t_s: np.ndarray
    x_m: np.ndarray
    y_m: np.ndarray
    theta_rad: np.ndarray
    true_x_m: np.ndarray
    true_y_m: np.ndarray
    true_theta_rad: np.ndarray


def belief_path(trace: TraceData) -> BeliefPath | None:
    """The app's odometry in the world's frame (None: no pose lines, or no true pose)."""
    spec = pose_line(trace.header)
    tr = trace.truth
    if spec is None or not {"x_m", "y_m", "theta_rad"} <= set(tr) or not len(tr["t_us"]):
        return None
    rows = telemetry.rows(telemetry.console_text(trace), spec.tag, spec.columns)
    if not len(rows["t_ms"]):
        return None
    t_s = (telemetry.firmware_t0_us(trace, spec.probe) + rows["t_ms"] * 1000) / US_PER_S
    x, y = rows[spec.columns[1]] * spec.m_per_unit, rows[spec.columns[2]] * spec.m_per_unit
    theta = np.unwrap(rows[spec.columns[3]] * spec.rad_per_unit)
    truth_t_s = tr["t_us"] / US_PER_S
    true_x, true_y = np.interp(t_s, truth_t_s, tr["x_m"]), np.interp(t_s, truth_t_s, tr["y_m"])
    true_theta = np.interp(t_s, truth_t_s, np.unwrap(tr["theta_rad"]))
    turn = true_theta[0] - theta[0]  # the odometry's frame, turned and moved onto the world's
    c, s = np.cos(turn), np.sin(turn)
    dx, dy = x - x[0], y - y[0]
    world_x, world_y = true_x[0] + c * dx - s * dy, true_y[0] + s * dx + c * dy
    return BeliefPath(spec.what, t_s, world_x, world_y, theta + turn, true_x, true_y, true_theta)


def odometry_panels(trace: TraceData) -> list[Panel]:
    path = belief_path(trace)
    if path is None:
        return []
    tr = trace.truth
    truth_t_s = tr["t_us"] / US_PER_S
    position = Panel(f"Position: the firmware's {path.what} against the truth (world frame)", "m")
    for axis, believed, true in (("x", path.x_m, tr["x_m"]), ("y", path.y_m, tr["y_m"])):
        position.lines.append(Line(f"true {axis}", truth_t_s, true))
        position.lines.append(Line(f"{axis} by {path.what} (firmware)", path.t_s, believed, "points"))
    heading = Panel(f"Heading: {path.what} against the truth", "heading (deg)")
    heading.lines.append(Line("true heading", truth_t_s, np.degrees(np.unwrap(tr["theta_rad"]))))
    heading.lines.append(Line(f"heading by {path.what} (firmware)", path.t_s, np.degrees(path.theta_rad), "points"))
    error = Panel(f"{path.what.capitalize()} error: how far the firmware's pose is from the true one", "m / deg")
    distance = np.hypot(path.x_m - path.true_x_m, path.y_m - path.true_y_m)
    error.lines.append(Line("position error (m)", path.t_s, distance))
    error.lines.append(Line("heading error (deg)", path.t_s, np.degrees(path.theta_rad - path.true_theta_rad)))
    error.notes.append(
        f"at the end: {distance[-1]:.3f} m and {np.degrees(path.theta_rad[-1] - path.true_theta_rad[-1]):+.1f} deg off"
    )
    return [position, heading, error]
