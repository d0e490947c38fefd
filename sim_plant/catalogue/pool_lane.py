"""Report view ``pool_lane``: what the pool cleaner's firmware believed against the truth,
from its ``lane`` telemetry lines (firmware/apps/pool_cleaner/mission.py) and the trace's
ground truth; a rig file names it in ``[report] views`` (firmware/apps/pool_cleaner/rig.toml).

The depth the firmware took from its side sonar against the true range of each sonar; the
Kalman estimate of the distance to the reference wall against the true distance, and the
lane it holds; the lane error and the estimate's error; the track stops it drove. The ADC
build adds its two inputs in metres through the firmware's own law, and says why an input
is flat. Drawn with the report's kit (``host/report/viewkit.py``), as a user's view is.
"""

import numpy as np

from sim_plant.catalogue.base import ReportView
from sim_plant.pool import BODY_WIDTH_M


class PoolLane(ReportView):
    kind = "pool_lane"
    doc = "The pool cleaner's lane: its sonar depth, Kalman estimate and lane error against the truth."

    def panels(self, trace, kit) -> list:
        return pool_cleaner_view(kit, trace)


LANE_COLUMNS = ("t_ms", "sonar", "depth_m", "d_m", "phi_rad", "ref_m", "stop_ms")
"""mission.py's LANE_LOG_COLUMNS: a ``lane`` line each second of closed loop."""
POOL_MIN_RANGE_M = 3.0  # mission.py MIN_RANGE_M: shorter readings are discarded
POOL_LANE_TOLERANCE_M = 0.1  # the scenarios' lane error bound (hil_tests/test_pool_cleaner.py)
ADC_VREF = 3.3  # firmware/lib/analog_depth_sounders.py: VREF, V_PER_M, MIN_M
ADC_V_PER_M = 0.33
ADC_MIN_M = 0.05
ADC_LAW = "read_u16 x 3.3 V / 65535 / 0.33 V/m (firmware/lib/analog_depth_sounders.py)"
ADC_SIDES = (("sonar_l.adc", "left", 0), ("sonar_r.adc", "right", 1))


def pool_cleaner_view(kit, trace) -> list:
    lane = kit.rows(kit.console_text(trace), "lane", LANE_COLUMNS)
    t_s = (kit.firmware_t0_us(trace) + lane["t_ms"] * 1000) / kit.US_PER_S
    panels = [pool_sonar_panel(kit, trace, lane, t_s)]
    if "sonar_l.adc" in trace.signals():
        panels.append(pool_adc_panel(kit, trace, lane))
    panels += [*pool_lane_panels(kit, trace, lane, t_s), pool_stops_panel(kit, trace)]
    return panels


def pool_sonar_panel(kit, trace, lane: dict, t_s: np.ndarray):
    panel = kit.Panel("Side sonar: the depth the firmware took against the true range of each sonar", "range (m)")
    tr = trace.truth
    for side, n in (("l", 0), ("r", 1)):
        column = f"sonar_{side}_range_m"
        if column in tr:
            true_m = np.where(np.isfinite(tr[column]), tr[column], np.nan)
            label = f"true range, {'left' if side == 'l' else 'right'} sonar (sonar {n})"
            panel.lines.append(kit.Line(label, tr["t_us"] / kit.US_PER_S, true_m))
    depth = np.where(lane["depth_m"] >= 0, lane["depth_m"], np.nan)
    panel.lines.append(kit.Line("depth the firmware took (the selected sonar; a line a second)", t_s, depth, "points"))
    panel.levels.append((POOL_MIN_RANGE_M, f"{POOL_MIN_RANGE_M:g} m: shorter readings discarded"))
    if len(lane["sonar"]) and lane["sonar"].max() >= 1:
        switch_s = t_s[np.argmax(lane["sonar"] >= 1)]
        panel.notes.append(f"sonar 1 (right) selected from t = {switch_s:.0f} s: d = width - its reading")
    if not len(t_s):
        panel.notes.append("no 'lane' lines in console.log: the firmware printed no belief to plot")
    return panel


def pool_adc_panel(kit, trace, lane: dict):
    """Both ADC inputs in metres, as the firmware converts them; a flat input said why."""
    panel = kit.Panel(f"ADC sonar inputs in metres: {ADC_LAW}", "range (m)")
    for signal, side, n in ADC_SIDES:
        t_us, u16 = trace.series(signal)
        metres = u16 * ADC_VREF / 65535 / ADC_V_PER_M
        panel.lines.append(kit.Line(f"{signal} ({side} sonar) in m", t_us / kit.US_PER_S, metres, "points"))
        if len(u16) and u16.min() == u16.max():
            panel.notes.append(_flat_input_note(kit, trace, signal, side, n, int(u16[0]), lane))
    return panel


def _flat_input_note(kit, trace, signal: str, side: str, n: int, u16: int, lane: dict) -> str:
    volts = u16 * ADC_VREF / 65535
    if volts / ADC_V_PER_M < ADC_MIN_M:
        what = f"{signal} stays at {volts:.2f} V, the sounder's 'no reading' (under {ADC_MIN_M:g} m)"
    else:
        what = f"{signal} stays at {volts / ADC_V_PER_M:.2f} m"
    true_m = trace.truth.get(f"sonar_{side[0]}_range_m")
    if true_m is not None and np.isfinite(true_m).any():
        finite = true_m[np.isfinite(true_m)]
        what += f": the {side} wall is {finite.min():.2f}-{finite.max():.2f} m away (truth)"
    used = len(lane["sonar"]) and (lane["sonar"] == n).any()
    return what + ("" if used else f"; the firmware never selected sonar {n} in this run, so never used it")


def pool_lane_panels(kit, trace, lane: dict, t_s: np.ndarray) -> list:
    estimate = kit.Panel("Lane: the Kalman estimate of d against the true distance to the reference wall", "d (m)")
    error = kit.Panel("Lane error", "error (m)")
    true_t_s, true_d = pool_true_distance_m(kit, trace)
    if len(true_d):
        estimate.lines.append(kit.Line("true d: reference wall to the left sonar (ground truth)", true_t_s, true_d))
    estimate.lines.append(kit.Line("Kalman estimate of d (firmware)", t_s, lane["d_m"], "points"))
    estimate.lines.append(kit.Line("lane the firmware holds (its reference)", t_s, lane["ref_m"], "dashed"))
    if len(true_d) and len(t_s):
        true_at = np.interp(t_s, true_t_s, true_d)
        error.lines.append(kit.Line("lane error: true d - lane held", t_s, true_at - lane["ref_m"], "points"))
        error.lines.append(kit.Line("estimate error: estimate - true d", t_s, lane["d_m"] - true_at, "points"))
        error.levels += [(POOL_LANE_TOLERANCE_M, "+-0.1 m"), (-POOL_LANE_TOLERANCE_M, "")]
    return [estimate, error]


def pool_true_distance_m(kit, trace) -> tuple[np.ndarray, np.ndarray]:
    """(t_s, metres) from the left sonar, on the body's side, to the reference wall (the
    pool's far side, y = width) across the lanes: what the filter's d estimates."""
    segments = (trace.header.get("world") or {}).get("segments")
    tr = trace.truth
    if not segments or "y_m" not in tr:
        return np.zeros(0), np.zeros(0)
    width_m = float(np.asarray(segments, dtype=float)[:, [1, 3]].max())
    return tr["t_us"] / kit.US_PER_S, width_m - tr["y_m"] - BODY_WIDTH_M / 2


def pool_stops_panel(kit, trace):
    panel = kit.Panel("Track stops the firmware drove (steering): left +1, right -1; both: the hold", "stopped")
    for signal, sign in (("track_l.stop", 1), ("track_r.stop", -1)):
        t_us, level = trace.series(signal)
        if len(t_us):
            panel.lines.append(kit.Line(signal, t_us / kit.US_PER_S, sign * level, "step"))
    return panel
