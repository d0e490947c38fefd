"""Budget statistics as a fixed-width text table, for terminals and logs, and the
session's summary: a headline (did the budgets hold?), a line per scenario with its
budgets' verdicts (:mod:`host.rig.config.verdicts`), the table of those that failed or missed."""

import textwrap

from host.rig.config import verdicts

FULL = ("scenario", "rig", "budget", "limit", "count", "p50", "p95", "p99", "max", "misses", "verdict")
NARROW = ("scenario", "rig", "budget", "limit", "count", "p50", "max", "misses", "verdict")


def format_table(rows: list[dict], cols=FULL) -> str:
    """Budget statistics as a fixed-width text table (one row per budget)."""
    cols = [c for c in cols if any(c in r for r in rows)]
    cells = [[("-" if r.get(c) is None else str(r.get(c))) for c in cols] for r in rows]
    widths = [max(len(c), *(len(row[i]) for row in cells)) for i, c in enumerate(cols)]
    line = "  ".join(c.ljust(w) for c, w in zip(cols, widths))
    out = [line.rstrip(), "  ".join("-" * w for w in widths)]
    out += ["  ".join(v.ljust(w) for v, w in zip(row, widths)).rstrip() for row in cells]
    return "\n".join(out)


WIDTH = 100  # the terminal summary's width when the terminal's is not known
NAME_MAX = 48  # a longer scenario name gets a line of its own, whole


def format_summary(rows: list[dict], failed: set[str] = frozenset(), width: int = WIDTH) -> str:
    """The headline; one line per scenario: how many budgets held, the worst one's
    verdict and why; then the full table of scenarios that failed or did not hold every
    budget. Names are never cut: one too long for the column has a line of its own."""
    scenarios: dict[str, list[dict]] = {}
    for row in rows:
        scenarios.setdefault(row["scenario"], []).append(row)
    column = min(max((len(n) for n in scenarios), default=0), NAME_MAX, max(width // 2, 10))
    out, detail = [verdicts.headline(rows)[1], ""], []
    for name, budgets in scenarios.items():
        text = scenario_verdict(budgets)
        out += _name_and_text(name, text, column, width)
        if name in failed or any(verdicts.verdict_of(b) in (verdicts.MISSED, verdicts.TOLERATED) for b in budgets):
            detail += budgets
    if detail:
        out += ["", "budgets of the scenarios that failed or did not hold every budget:", *_detail(detail)]
    return "\n".join(out)


def _detail(rows: list[dict]) -> list[str]:
    """One table (the columns aligned throughout), each scenario's rows under its whole name."""
    lines = format_table(rows, NARROW[1:]).splitlines()
    out, last = ["  " + line for line in lines[:2]], None
    for row, line in zip(rows, lines[2:]):
        if row["scenario"] != last:
            out.append(f"{row['scenario']}:")
            last = row["scenario"]
        out.append("  " + line)
    return out


def scenario_verdict(budgets: list[dict]) -> str:
    """``all 3 held``, or the worst budget's verdict: ``MISSED name n/count, max ...``
    or ``tolerated name n/count (why)``."""
    judged = [b for b in budgets if verdicts.verdict_of(b) not in (verdicts.INFO, verdicts.UNMEASURED)]
    missed = [b for b in judged if verdicts.verdict_of(b) == verdicts.MISSED]
    tolerated = [b for b in judged if verdicts.verdict_of(b) == verdicts.TOLERATED]
    if not missed and not tolerated:
        return f"all {len(judged)} held"
    worst = max(missed or tolerated, key=lambda b: b["misses"])
    held = len(judged) - len(missed) - len(tolerated)
    if missed:
        text = f"MISSED {worst['budget']} {worst['misses']}/{worst['count']}, max {worst['max']} ({worst['limit']})"
    else:
        text = f"tolerated {worst['budget']} {worst['misses']}/{worst['count']} ({worst.get('why') or 'not judged'})"
    more = [
        f"{len(group) - (worst in group)} more {name}" for name, group in (("missed", missed), ("tolerated", tolerated))
    ]
    return "; ".join([text, *(m for m in more if not m.startswith("0 ")), f"{held} held"])


def _name_and_text(name: str, text: str, column: int, width: int) -> list[str]:
    if len(name) > column:  # its own line, the verdict under it
        return [name, *textwrap.wrap(text, width, initial_indent="    ", subsequent_indent="      ")]
    indent = " " * (column + 1)
    lines = textwrap.wrap(text, max(width - column - 1, 20), subsequent_indent="  ")
    return [f"{name:<{column}} {lines[0]}".rstrip(), *(indent + line for line in lines[1:])]
