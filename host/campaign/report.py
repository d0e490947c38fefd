"""A campaign's results people can use (``docs/campaigns.md``): per (fault set, world) the
success rate with its 95 % Wilson interval and each figure's spread; the figures'
distributions as plots; the worst runs by the judged figure, with their seed, a map of
the floor each missed and the command that replays each; an HTML page with its images
in files beside it (:mod:`.page`), and CSV and JSON; the lines the command prints."""

import csv
import json
import math
import shlex
from pathlib import Path

import numpy as np

from host.campaign.maps import coverage_maps
from host.campaign.metrics import judged_by, metric
from host.campaign.page import expectation, render
from host.campaign.store import RESULTS
from host.core import safefs
from host.core.errors import HarnessError, OutputRefused

Z_95 = 1.959964
WORST_RUNS = 8


def wilson(successes: int, n: int, z: float = Z_95) -> tuple[float, float]:
    """The Wilson score interval of a success rate (95 % by default). It holds the rate
    and stays in [0, 1]: in floating point the bound of an all-passing group comes out a
    hair under 1 (10 of 10: 0.9999999999999999), of an all-failing one a hair over 0, so
    the bounds are clamped to the rate (the exact interval reaches it there)."""
    if n == 0:
        return 0.0, 1.0
    p = successes / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return max(0.0, min(p, centre - half)), min(1.0, max(p, centre + half))


def error_bars(rows: list[dict]) -> list[list[float]]:
    """The success-rate plot's bars: how far each group's interval reaches below and
    above its rate, never negative (an interval from an older ``summary.json`` may miss
    its rate by a rounding)."""
    below = [max(0.0, r["rate"] - r["wilson_lo"]) for r in rows]
    above = [max(0.0, r["wilson_hi"] - r["rate"]) for r in rows]
    return [below, above]


def _quantile(values: list[float], q: float) -> float:
    values = sorted(v for v in values if not math.isnan(v))
    if not values:
        return math.nan
    pos = q * (len(values) - 1)
    lo = math.floor(pos)
    hi = min(lo + 1, len(values) - 1)
    return values[lo] + (values[hi] - values[lo]) * (pos - lo)


def summarize(results: list[dict]) -> list[dict]:
    """One row per (fault set, world): runs, passes, rate, Wilson interval, errors by kind,
    each figure's median and 5/95 % quantiles, the median wall time."""
    groups: dict[tuple, list] = {}
    for r in results:
        groups.setdefault((r["faultset"], r["world"]), []).append(r)
    rows = []
    for (faultset, world), runs in sorted(groups.items()):
        n, k = len(runs), sum(1 for r in runs if r["passed"])
        lo, hi = wilson(k, n)
        errors: dict[str, int] = {}
        for r in runs:
            if r.get("error"):
                errors[r["error"]] = errors.get(r["error"], 0) + 1
        figures = {}
        for name in sorted({f for r in runs for f in r["figures"]}):
            values = [r["figures"][name] for r in runs if name in r["figures"]]
            figures[name] = {q: _quantile(values, v) for q, v in (("p5", 0.05), ("median", 0.5), ("p95", 0.95))}
        rows.append(
            {
                "faultset": faultset,
                "world": world,
                "runs": n,
                "passed": k,
                "rate": k / n,
                "wilson_lo": lo,
                "wilson_hi": hi,
                "errors": errors,
                "figures": figures,
                "wall_s_median": _quantile([r.get("wall_s", 0.0) for r in runs], 0.5),
                "cpu_s_median": _quantile([r["cpu_s"] for r in runs if "cpu_s" in r], 0.5),
            }
        )
    return rows


def worst(results: list[dict], by: str | None, low: bool = False, n: int = WORST_RUNS) -> list[dict]:
    """The ``n`` worst runs: the failed runs first, then the passes; within each, a run
    without the figure ``by`` (one that ended in an error) first, then by ``by``, worst
    first (the lowest when ``low``: coverage; the highest otherwise: time, distance);
    ties by fault set, world and seed."""

    def rank(r):
        v = r["figures"].get(by, math.nan) if by else math.nan
        missing = v is None or not math.isfinite(v)
        badness = 0.0 if missing else (v if low else -v)
        return (bool(r["passed"]), not missing, badness, r["faultset"], r["world"], r["seed"])

    return sorted(results, key=rank)[:n]


def summary_lines(campaign: dict, results: list[dict]) -> list[str]:
    """What ``mpy-fil campaign`` prints at the end: per group, n passed of n, the rate and
    its Wilson bounds, whether that is a showcase's expected figure; the failures by
    reason, and the worst runs by the judged figure."""
    by, low = judged_by(campaign, results)
    m = metric(by)
    lines = []
    for row in summarize(results):
        runs = [r for r in results if (r["faultset"], r["world"]) == (row["faultset"], row["world"])]
        line = (
            f"  {row['faultset']} / {row['world']}: {row['passed']} of {row['runs']} passed, "
            f"{row['rate']:.0%} [95 % Wilson {row['wilson_lo']:.0%}-{row['wilson_hi']:.0%}]"
        )
        note = expectation(campaign, row)
        lines.append(line + (f": {note}" if note else ""))
        reasons: dict[str, int] = {}
        for r in runs:
            if not r["passed"]:
                reason = ((r.get("message") or r.get("error") or "failed").splitlines() or ["failed"])[0]
                reason = reason.split(", got ")[0][:100]
                reasons[reason] = reasons.get(reason, 0) + 1
        for reason, count in sorted(reasons.items(), key=lambda kv: -kv[1]):
            lines.append(f"    {count} failed: {reason}")
        bad = [r for r in worst(runs, by, low, n=5) if not r["passed"] or len(runs) > 5]
        if bad:
            shown = ", ".join(f"seed {r['seed']} ({m.show(r['figures'].get(by))})" for r in bad)
            lines.append(f"    worst by {m.label}: {shown}")
    return lines


def progress_line(r: dict, done: int, total: int, by: str, rate_per_min: float) -> str:
    """One short line per finished run: pass or fail, its key, the judged figure, the
    wall time; a failure's reason cut to its first 100 characters."""
    m = metric(by)
    value = r["figures"].get(by)
    figure = f" {m.label} {m.show(value)}" if value is not None else ""
    first = ((r.get("message") or "").splitlines() or [""])[0]
    why = f": {first[:100]}" if not r["passed"] and first else ""
    return (
        f"[{done}/{total}] {'pass' if r['passed'] else 'fail'} {r['key']}{figure}, {r.get('wall_s', 0):.0f} s"
        f"{why}  ({rate_per_min:.1f} runs/min)"
    )


def replay_command(out: Path, key: str) -> str:
    """The one line that runs ``key`` again, traced and recorded, from the campaign folder."""
    return f".venv/bin/mpy-fil campaign --replay {shlex.quote(key)} --out {shlex.quote(str(out))}"


class ReportError(HarnessError):
    """The report could not be written; the results it was made of are kept."""


def write_report(out: Path, campaign: dict, results: list[dict]) -> dict:
    """``summary.json``, ``summary.csv``, ``runs.csv``, ``plots/*.png`` and
    ``campaign.html`` in ``out``; the paths written. The results are in
    ``results.jsonl`` before this is called: whatever fails here (a plot, a full disk)
    is a :class:`ReportError` in one line that says where they are."""
    out = Path(out)
    try:
        return _write_report(out, campaign, results)
    except OutputRefused:  # (a link where a file of the report goes: named as such)
        raise
    except Exception as e:  # the report is derived data: say so, name what is kept
        first = (str(e).strip().splitlines() or [""])[0][:200]
        raise ReportError(
            f"the report in {out} was not written ({type(e).__name__}: {first}); the {len(results)} results are "
            f"kept in {out / RESULTS}: the same command writes the report again without running them"
        ) from e


def _write_report(out: Path, campaign: dict, results: list[dict]) -> dict:
    rows = summarize(results)
    by, low = judged_by(campaign, results)
    worst_runs = [dict(r) for r in worst(results, by, low)]
    for r in worst_runs:
        r["replay"] = replay_command(out, r["key"])
    summary = {"campaign": campaign, "groups": rows, "worst": worst_runs, "worst_by": by, "runs": len(results)}
    safefs.write_text(out / "summary.json", json.dumps(summary, indent=1, default=str) + "\n")
    _write_group_csv(out / "summary.csv", rows)
    _write_runs_csv(out / "runs.csv", results)
    plots = _plots(out / "plots", results, rows)
    maps = coverage_maps(out, worst_runs)
    page = out / "campaign.html"
    safefs.write_text(page, render(campaign, rows, worst_runs, plots, maps, len(results), (by, low)))
    return {"html": page, "json": out / "summary.json", "csv": out / "summary.csv", "runs_csv": out / "runs.csv"}


def _write_group_csv(path: Path, rows: list[dict]) -> None:
    names = sorted({f for r in rows for f in r["figures"]})
    with safefs.open_write(path, "w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        head = ["faultset", "world", "runs", "passed", "rate", "wilson_lo", "wilson_hi"]
        w.writerow(head + [f"{n}_{q}" for n in names for q in ("p5", "median", "p95")])
        for r in rows:
            figs = [r["figures"].get(n, {}).get(q, "") for n in names for q in ("p5", "median", "p95")]
            w.writerow([r[h] for h in head] + figs)


def _write_runs_csv(path: Path, results: list[dict]) -> None:
    names = sorted({f for r in results for f in r["figures"]})
    with safefs.open_write(path, "w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(["faultset", "world", "seed", "passed", "error", "t_end_s", "wall_s", *names, "message"])
        for r in sorted(results, key=lambda r: (r["faultset"], r["world"], r["seed"])):
            figs = [r["figures"].get(n, "") for n in names]
            first = (r.get("message") or "").splitlines()[:1]
            w.writerow(
                [
                    r["faultset"],
                    r["world"],
                    r["seed"],
                    int(r["passed"]),
                    r.get("error") or "",
                    r["t_end_s"],
                    r.get("wall_s", 0),
                    *figs,
                    first[0] if first else "",
                ]
            )


def _plots(folder: Path, results: list[dict], rows: list[dict]) -> list[Path]:
    """The success rate per group with its interval, and one histogram per figure (and the
    wall time), a series per group."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    folder = safefs.make_folder(folder)  # (plots/ a link: refused)
    paths = []
    labels = [f"{r['faultset']} / {r['world']}" for r in rows]
    fig, ax = plt.subplots(figsize=(7, 1.6 + 0.45 * len(rows)))
    rates = [r["rate"] for r in rows]
    ax.errorbar(rates, range(len(rows)), xerr=error_bars(rows), fmt="o", capsize=4)
    ax.set_yticks(range(len(rows)), labels)
    ax.set_xlim(-0.02, 1.02)
    ax.set_xlabel("success rate (95 % Wilson interval)")
    fig.tight_layout()
    paths.append(_save(fig, folder / "success_rate.png"))
    names = sorted({f for r in results for f in r["figures"]}) + ["wall_s"]
    for name in names:
        paths.append(_histogram(plt, folder / f"{name}.png", name, results, rows, labels))
    return paths


def histogram_bins(values: list[float], integer: bool) -> np.ndarray:
    """The same bins for every group, so their bars compare; a count's bins are whole
    numbers, centred on each (one a value, or a few values each when they spread wide)."""
    if integer:
        lo, hi = math.floor(min(values)), math.ceil(max(values))
        step = max(1, math.ceil((hi - lo + 1) / 30))
        return np.arange(lo - 0.5, hi + step + 0.5, step)
    return np.histogram_bin_edges(values, bins=min(30, max(5, len(values) // 3)))


def _histogram(plt, path: Path, name: str, results: list[dict], rows: list[dict], labels: list[str]) -> Path:
    m = metric(name)
    fig, ax = plt.subplots(figsize=(7, 3.2))
    series = []
    for row, label in zip(rows, labels):
        values = [
            (r["figures"].get(name) if name != "wall_s" else r.get("wall_s"))
            for r in results
            if (r["faultset"], r["world"]) == (row["faultset"], row["world"])
        ]
        series.append(([m.scaled(v) for v in values if v is not None and math.isfinite(v)], label))
    every = [v for values, _ in series for v in values]
    if every:
        bins = histogram_bins(every, m.integer)
        for values, label in series:
            if values:
                ax.hist(values, bins=bins, alpha=0.6, label=label)
        if m.integer:
            ax.xaxis.get_major_locator().set_params(integer=True)
    ax.yaxis.get_major_locator().set_params(integer=True)
    ax.set_xlabel(m.title)
    ax.set_ylabel("runs")
    ax.set_title(m.label[:1].upper() + m.label[1:], fontsize="medium")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize="small")
    fig.tight_layout()
    return _save(fig, path)


def _save(fig, path: Path) -> Path:
    import matplotlib.pyplot as plt

    with safefs.replacing(path) as temp:  # (a link at the name replaced, never written through)
        fig.savefig(temp, dpi=90, format="png")
    plt.close(fig)
    return path


def _num(v) -> str:
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "-"
    return f"{v:.3g}"
