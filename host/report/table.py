"""Budget statistics as a fixed-width text table, for terminals and logs."""


def format_table(rows: list[dict]) -> str:
    """Budget statistics as a fixed-width text table (one row per budget)."""
    cols = ["scenario", "budget", "limit", "count", "p50", "p95", "p99", "max", "misses"]
    cols = [c for c in cols if any(c in r for r in rows)]
    cells = [[("-" if r.get(c) is None else str(r.get(c))) for c in cols] for r in rows]
    widths = [max(len(c), *(len(row[i]) for row in cells)) for i, c in enumerate(cols)]
    line = "  ".join(c.ljust(w) for c, w in zip(cols, widths))
    out = [line, "  ".join("-" * w for w in widths)]
    out += ["  ".join(v.ljust(w) for v, w in zip(row, widths)) for row in cells]
    return "\n".join(out)
