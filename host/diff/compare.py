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

A verdict (:meth:`Diff.beyond`) names each threshold exceeded. A value that is no number
(NaN, inf) where a number must be (a pose, a firmware output) is named
(:attr:`Diff.uncompared`): such a diff is never "same". A sensor's ground truth may be
inf or NaN (nothing in range): the same on both sides is no difference, on one side only
it is one, and named in a note.

Every signal kind the recorder keeps is compared: numbers, and text (a bus's transfers,
a display's text, bytes as hex, an LED's colour), value by value.
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
    uncompared: list[str] = field(default_factory=list)  # what is no number where one must be

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
    diff.outputs = compare_outputs(a, b, diff.uncompared)
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
    for name in (*POSE, HEADING):
        for side, trace, index in (("A", diff.a, ia), ("B", diff.b, ib)):
            if name in trace.truth:
                _name_non_finite(diff, f"{side}'s {name}", trace.truth[name][index], diff.t_s, "the pose")
    if all(n in names for n in POSE):
        dx = diff.a.truth["x_m"][ia] - diff.b.truth["x_m"][ib]
        dy = diff.a.truth["y_m"][ia] - diff.b.truth["y_m"][ib]
        diff.position_m = np.hypot(dx, dy)
        diff.fields.append(_row("position (m)", diff.t_s, diff.position_m))
    for name in names:
        va, vb = diff.a.truth[name][ia], diff.b.truth[name][ib]
        with np.errstate(invalid="ignore"):
            d = np.abs(va - vb)
        if name == HEADING:
            d = np.abs((va - vb + math.pi) % (2 * math.pi) - math.pi)
        same = _same_non_finite(va, vb)  # (nan and nan, inf and inf: nothing in range on both)
        apart = ~np.isfinite(va) | ~np.isfinite(vb)
        d = np.where(same, 0.0, np.where(apart, math.inf, d))
        if np.any(apart & ~same):
            i = int(np.argmax(apart & ~same))
            diff.notes.append(
                f"{name} at t={diff.t_s[i]:.6f} s: {va[i]:g} in A, {vb[i]:g} in B (not a number on one side)"
            )
        diff.fields.append(_row(name, diff.t_s, d))


def _same_non_finite(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Where both are the same non-number: NaN and NaN, or inf and inf of one sign."""
    return (np.isnan(a) & np.isnan(b)) | (np.isinf(a) & (a == b))


def _name_non_finite(diff: Diff, what: str, values: np.ndarray, t_s: np.ndarray, where: str) -> None:
    bad = ~np.isfinite(np.asarray(values, dtype=float))
    if np.any(bad):
        i = int(np.argmax(bad))
        diff.uncompared.append(
            f"{what} is {values[i]:g} at t={t_s[i]:.6f} s ({int(bad.sum())} of {len(bad)} rows): {where} is no number"
        )


def _row(name: str, t_s: np.ndarray, d: np.ndarray) -> dict:
    both = np.where(np.isnan(d), 0.0, d)  # (a pose that is no number: named in Diff.uncompared)
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


def compare_outputs(a: TraceData, b: TraceData, uncompared: list | None = None) -> list[dict]:
    """A row per firmware output of either: its change counts and its first divergence
    (values of any kind: numbers or text); a value that is no number (NaN, inf) is named
    in ``uncompared``."""
    changes: dict[str, tuple[list, list]] = {n: ([], []) for n in set(firmware_outputs(a)) | set(firmware_outputs(b))}
    for side, trace in enumerate((a, b)):
        for t_us, name, value in trace.events:
            if name in changes:
                changes[name][side].append((t_us, value))
    rows = []
    for name in sorted(changes):
        ea, eb = changes[name]
        for side, events in (("A", ea), ("B", eb)):
            bad = [(t, v) for t, v in events if isinstance(v, float) and not math.isfinite(v)]
            if bad and uncompared is not None:
                uncompared.append(
                    f"output {name} is {bad[0][1]:g} in {side} at t={bad[0][0] / 1e6:.6f} s ({len(bad)} of "
                    f"{len(events)} changes): a firmware output is no number"
                )
        first = next((i for i, (x, y) in enumerate(zip(ea, eb)) if not _same_change(x, y)), None)
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


def _same_change(x: tuple, y: tuple) -> bool:
    """Two changes at one time to one value (NaN is NaN: named apart, in Diff.uncompared)."""
    if x[0] != y[0]:
        return False
    a, b = x[1], y[1]
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return True
    return a == b


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
