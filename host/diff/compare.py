"""Two trace folders (``host.artefacts.folder.load_trace``) compared:

- **trajectory**: each numeric truth field both have (``truth.csv``), on the times both
  have (``truth_period_us`` apart), its largest and RMS difference and when the largest
  was; the position (``x_m``, ``y_m``) as one distance, the heading (``theta_rad``)
  wrapped to +-pi;
- **outputs**: each firmware output (the header's signals that are not sensors), its
  changes in order: the first change that differs (in time or value), with its virtual
  time, or none;
- **budgets**: each budget's p50, p99 and misses in A and B, and their change; wall-clock
  budgets are listed but never judged (they change run to run).

A verdict (:meth:`Diff.beyond`) names each threshold exceeded.
"""

import math
from dataclasses import dataclass, field

import numpy as np

from host.artefacts.folder import TraceData
from host.artefacts.recorder import ROLE_SENSOR

POSE = ("x_m", "y_m")
HEADING = "theta_rad"


@dataclass
class Thresholds:
    max_pos_m: float = 0.0
    max_rms_m: float = 0.0
    fail_on_output: bool = False
    max_p99_change_us: float | None = None
    max_misses_change: int | None = None


@dataclass
class Diff:
    a: TraceData
    b: TraceData
    t_s: np.ndarray = field(default_factory=lambda: np.zeros(0))  # the common truth times
    position_m: np.ndarray = field(default_factory=lambda: np.zeros(0))  # the distance between the poses
    fields: list[dict] = field(default_factory=list)
    outputs: list[dict] = field(default_factory=list)
    budgets: list[dict] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)

    @property
    def max_pos_m(self) -> float:
        return float(np.nanmax(self.position_m)) if len(self.position_m) else 0.0

    @property
    def rms_pos_m(self) -> float:
        return float(np.sqrt(np.nanmean(self.position_m**2))) if len(self.position_m) else 0.0

    def first_divergence(self) -> dict | None:
        diverged = [o for o in self.outputs if o["first_t_s"] is not None]
        return min(diverged, key=lambda o: o["first_t_s"]) if diverged else None

    def beyond(self, limits: Thresholds) -> list[str]:
        """Each threshold exceeded, as a sentence; empty when within them all."""
        out = []
        if self.max_pos_m > limits.max_pos_m:
            out.append(f"position differs by up to {self.max_pos_m:.4f} m (--max-pos-m {limits.max_pos_m:g})")
        if self.rms_pos_m > limits.max_rms_m:
            out.append(f"position RMS difference {self.rms_pos_m:.4f} m (--max-rms-m {limits.max_rms_m:g})")
        first = self.first_divergence()
        if limits.fail_on_output and first is not None:
            out.append(f"output {first['signal']} first differs at t={first['first_t_s']:.6f} s (--fail-on-output)")
        for row in self.budgets:
            if row["wall_clock"]:
                continue
            if limits.max_p99_change_us is not None and abs(row["p99_change"] or 0) > limits.max_p99_change_us:
                out.append(f"budget {row['budget']} p99 changed by {row['p99_change']:g} us (--max-p99-change-us)")
            if limits.max_misses_change is not None and (row["misses_change"] or 0) > limits.max_misses_change:
                out.append(f"budget {row['budget']} misses rose by {row['misses_change']} (--max-misses-change)")
        return out


def compare(a: TraceData, b: TraceData) -> Diff:
    diff = Diff(a, b)
    compare_truth(diff)
    diff.outputs = compare_outputs(a, b)
    diff.budgets = compare_budgets(a.budgets, b.budgets)
    return diff


def compare_truth(diff: Diff) -> None:
    ta, tb = diff.a.truth.get("t_us"), diff.b.truth.get("t_us")
    names = [n for n in diff.a.truth if n != "t_us" and n in diff.b.truth]
    if ta is None or tb is None or not names:
        missing = "A" if len(diff.a.truth) <= 1 else "B"
        diff.notes.append(f"trajectory not compared: {missing} has no ground truth (a replay's plant has none)")
        return
    t, ia, ib = np.intersect1d(ta, tb, return_indices=True)
    if len(ta) != len(tb):
        diff.notes.append(f"truth compared over the {len(t)} times both have (A {len(ta)}, B {len(tb)} rows)")
    diff.t_s = t / 1e6
    if all(n in names for n in POSE):
        dx = diff.a.truth["x_m"][ia] - diff.b.truth["x_m"][ib]
        dy = diff.a.truth["y_m"][ia] - diff.b.truth["y_m"][ib]
        diff.position_m = np.hypot(dx, dy)
        diff.fields.append(_row("position (m)", diff.t_s, diff.position_m))
    for name in names:
        with np.errstate(invalid="ignore"):  # (inf - inf: a reading out of range on both: no difference)
            d = diff.a.truth[name][ia] - diff.b.truth[name][ib]
        if name == HEADING:
            d = (d + math.pi) % (2 * math.pi) - math.pi
        diff.fields.append(_row(name, diff.t_s, np.abs(d)))


def _row(name: str, t_s: np.ndarray, d: np.ndarray) -> dict:
    both = np.where(np.isnan(d), 0.0, d)  # (a field neither knew yet: no difference)
    i = int(np.argmax(both)) if len(both) else 0
    finite = both[np.isfinite(both)]
    return {
        "field": name,
        "max": float(both[i]) if len(both) else 0.0,
        "rms": float(np.sqrt(np.mean(finite**2))) if len(finite) else 0.0,
        "at_s": float(t_s[i]) if len(both) and both[i] > 0 else None,
    }


def firmware_outputs(trace: TraceData) -> list[str]:
    return sorted(n for n, info in trace.signals().items() if info["role"] != ROLE_SENSOR)


def compare_outputs(a: TraceData, b: TraceData) -> list[dict]:
    """A row per firmware output of either: its change counts and its first divergence."""
    changes: dict[str, tuple[list, list]] = {n: ([], []) for n in set(firmware_outputs(a)) | set(firmware_outputs(b))}
    for side, trace in enumerate((a, b)):
        for t_us, name, value in trace.events:
            if name in changes:
                changes[name][side].append((t_us, value))
    rows = []
    for name in sorted(changes):
        ea, eb = changes[name]
        first = next((i for i, (x, y) in enumerate(zip(ea, eb)) if x != y), None)
        if first is None and len(ea) != len(eb):
            first = min(len(ea), len(eb))
        row = {"signal": name, "changes_a": len(ea), "changes_b": len(eb), "first_t_s": None, "a": "", "b": ""}
        if first is not None:
            xa, xb = (ea[first] if first < len(ea) else None), (eb[first] if first < len(eb) else None)
            row["first_t_s"] = min(x[0] for x in (xa, xb) if x is not None) / 1e6
            row["a"] = _change_text(xa)
            row["b"] = _change_text(xb)
        rows.append(row)
    return rows


def _change_text(change) -> str:
    return "(none)" if change is None else f"{change[1]} at {change[0] / 1e6:.6f} s"


def compare_budgets(a: list[dict], b: list[dict]) -> list[dict]:
    """A row per budget of either: p50, p99, misses in A and B, and the changes."""
    by_a, by_b = {x["name"]: x for x in a}, {x["name"]: x for x in b}
    rows = []
    for name in list(by_a) + [n for n in by_b if n not in by_a]:
        sa, sb = (by_a.get(name) or {}).get("stats") or {}, (by_b.get(name) or {}).get("stats") or {}
        row = {"budget": name, "wall_clock": bool((by_a.get(name) or by_b.get(name)).get("wall_clock"))}
        for stat in ("p50", "p99", "misses"):
            row[f"{stat}_a"], row[f"{stat}_b"] = sa.get(stat), sb.get(stat)
            both = sa.get(stat) is not None and sb.get(stat) is not None
            row[f"{stat}_change"] = sb[stat] - sa[stat] if both else None
        rows.append(row)
    return rows
