"""``mpy-fil diff A B``: the two trace folders compared (:mod:`.compare`), as tables on the
terminal and a plot (:mod:`.plot`); exit status 0 when within every threshold, 1 beyond
one (each named), 2 when they could not be compared: a folder that cannot be read or is
damaged (the command line's one line, :class:`CannotCompare` or another ConfigError), or a
pose or output that is no number (NaN, inf: each named). The command line hands in
``say``."""

import argparse
import math
from pathlib import Path

from host.artefacts.folder import HEADER, load_trace, set_boards
from host.core import safefs
from host.core.errors import ConfigError
from host.diff.compare import Thresholds, compare
from host.diff.plot import plot_diff
from host.report.table import format_table

EXIT_SAME, EXIT_DIFFERS, EXIT_CANNOT_COMPARE = 0, 1, 2


class CannotCompare(ConfigError):
    """Two trace folders that could not be compared (exit 2, not 1: "differs")."""


def thresholds(args) -> Thresholds:
    limits = Thresholds(
        max_pos_m=args.max_pos_m,
        max_rms_m=args.max_rms_m,
        fail_on_output=args.fail_on_output,
        max_p99_change_us=args.max_p99_change_us,
        max_misses_change=args.max_misses_change,
    )
    for name in ("max_pos_m", "max_rms_m", "max_p99_change_us", "max_misses_change"):
        value = getattr(limits, name)
        if value is not None and not (math.isfinite(value) and value >= 0):
            raise ConfigError(f"--{name.replace('_', '-')}: expected a number >= 0, got {value}")
    return limits


def _out(args) -> Path:
    """The plot's folder (default ``B/diff``): never A or B, around them or inside them but
    for their ``diff/`` (:func:`host.core.safefs.output_folder`)."""
    folders = {"the trace folder A": args.a, "the trace folder B": args.b}
    return safefs.output_folder(
        Path(args.out) if args.out else Path(args.b) / "diff",
        what="--out",
        inputs=folders,
        owned=dict.fromkeys(folders, "diff"),
        base=None if args.out else args.b,
    )


def diff_command(args, say) -> int:
    limits = thresholds(args)
    out = _out(args)
    a_boards, b_boards = (set_boards(f) if not (Path(f) / HEADER).is_file() else None for f in (args.a, args.b))
    if a_boards is None and b_boards is None:
        return _diff_folders(args.a, args.b, out, limits, say)
    if a_boards != b_boards:
        what = lambda boards: f"the boards {', '.join(boards)}" if boards else "one board's trace folder"  # noqa: E731
        raise CannotCompare(f"A {args.a} holds {what(a_boards)} and B {args.b} {what(b_boards)}: not the same set")
    worst = EXIT_SAME  # (a set of boards: board by board, each plot in out/<board>; the worst exit)
    for board in a_boards:
        say(f"board {board}:")
        done = _diff_folders(Path(args.a) / board, Path(args.b) / board, out / board, limits, say, f"board {board}: ")
        worst = max(worst, done)
    return worst


def _diff_folders(a_folder: Path, b_folder: Path, out: Path, limits, say, label: str = "") -> int:
    args = argparse.Namespace(a=a_folder, b=b_folder)
    a, b = load_trace(args.a), load_trace(args.b)
    try:
        diff = compare(a, b)
    except (ValueError, TypeError, KeyError, IndexError, ArithmeticError) as e:
        raise CannotCompare(f"A {args.a} and B {args.b} could not be compared: {type(e).__name__}: {e}") from e
    say(f"A: {args.a} ({a.header['app']}, seed {a.header['seed']}, {a.header['t_end_us'] / 1e6:g} s)")
    say(f"B: {args.b} ({b.header['app']}, seed {b.header['seed']}, {b.header['t_end_us'] / 1e6:g} s)")
    for line in report_lines(diff):
        say(line)
    try:
        say(f"plot: {plot_diff(diff, out)}")
    except OSError as e:  # (a full disk: the verdict stands, and its exit status)
        say(f"plot: not written ({e.filename or out}: {e.strerror or e})")
    beyond = diff.beyond(limits)
    if beyond:
        say(f"{label}DIFFERS beyond the thresholds: " + "; ".join(beyond))
        return EXIT_DIFFERS
    if diff.uncompared:
        say(f"{label}could not compare: " + "; ".join(diff.uncompared))
        return EXIT_CANNOT_COMPARE
    say(f"{label}same within the thresholds")
    return EXIT_SAME


def report_lines(diff) -> list[str]:
    """The trajectory, outputs and budgets tables, with the notes."""
    out = []
    if diff.fields:
        out += ["", "trajectory (ground truth, |A - B| over the common times):"]
        rows = [
            {"field": f["field"], "max": f"{f['max']:.6g}", "rms": f"{f['rms']:.6g}", "at (s)": _t(f["at_s"])}
            for f in diff.fields
        ]
        out += format_table(rows, ("field", "max", "rms", "at (s)")).splitlines()
    out += ["", "firmware outputs (their changes in order):"]
    rows = [
        {
            "output": o["signal"],
            "changes A": o["changes_a"],
            "changes B": o["changes_b"],
            "first divergence (s)": _t(o["first_t_s"]) if o["first_t_s"] is not None else "same",
            "A": o["a"],
            "B": o["b"],
        }
        for o in diff.outputs
    ]
    out += format_table(rows, ("output", "changes A", "changes B", "first divergence (s)", "A", "B")).splitlines()
    if diff.budgets:
        out += ["", "budgets (us; wall-clock ones informational):"]
        cols = ("budget", "p50 A", "p50 B", "p99 A", "p99 B", "p99 change", "misses A", "misses B", "misses change")
        rows = [
            {
                "budget": r["budget"] + (" (wall)" if r["wall_clock"] else ""),
                **{f"{s} {side}": r[f"{s}_{side.lower()}"] for s in ("p50", "p99", "misses") for side in "AB"},
                "p99 change": r["p99_change"],
                "misses change": r["misses_change"],
            }
            for r in diff.budgets
        ]
        out += format_table(rows, cols).splitlines()
    out += [f"note: {n}" for n in diff.notes]
    return out


def _t(t_s) -> str:
    return "-" if t_s is None else f"{t_s:.6f}"
