"""Budget statistics as a fixed-width text table, for terminals and logs."""

FULL = ("scenario", "budget", "limit", "count", "p50", "p95", "p99", "max", "misses")
NARROW = ("scenario", "budget", "limit", "count", "p50", "max", "misses")


def format_table(rows: list[dict], cols=FULL) -> str:
    """Budget statistics as a fixed-width text table (one row per budget)."""
    cols = [c for c in cols if any(c in r for r in rows)]
    cells = [[("-" if r.get(c) is None else str(r.get(c))) for c in cols] for r in rows]
    widths = [max(len(c), *(len(row[i]) for row in cells)) for i, c in enumerate(cols)]
    line = "  ".join(c.ljust(w) for c, w in zip(cols, widths))
    out = [line, "  ".join("-" * w for w in widths)]
    out += ["  ".join(v.ljust(w) for v, w in zip(row, widths)) for row in cells]
    return "\n".join(out)


WIDTH = 100  # the terminal summary fits this many columns


def format_summary(rows: list[dict], failed: set[str] = frozenset()) -> str:
    """One line per scenario: how many budgets held, and the worst one (most misses, the
    wall-clock ones being informational); then the full table of scenarios that failed or
    missed a budget."""
    scenarios: dict[str, list[dict]] = {}
    for row in rows:
        scenarios.setdefault(row["scenario"], []).append(row)
    out, detail = [], []
    for name, budgets in scenarios.items():
        enforced = [b for b in budgets if "wall" not in str(b.get("limit", ""))]
        missed = [b for b in enforced if b.get("misses")]
        if missed:
            worst = max(missed, key=lambda b: b["misses"])
            verdict = (
                f"MISSED {worst['budget']} {worst['misses']}/{worst['count']}, max {worst['max']} ({worst['limit']})"
            )
        else:
            verdict = f"all {len(enforced)} held"
        out.append(f"{_short(name):<40} {verdict}"[:WIDTH])
        if missed or name in failed:
            detail += budgets
    if detail:
        short = [{**row, "scenario": _short(row["scenario"], 30)} for row in detail]
        out += ["", "budgets of the scenarios that failed or missed:", format_table(short, NARROW)]
    return "\n".join(out)


def _short(name: str, width: int = 40) -> str:
    return name if len(name) <= width else name[: width - 3] + "..."
