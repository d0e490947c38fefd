"""A campaign's results people can use (``docs/campaigns.md``): per (fault set, world) the
success rate with its 95 % Wilson interval and each figure's spread; the figures'
distributions as plots; the worst runs with their seed and the command that replays
each; one self-contained HTML page, and CSV and JSON beside it."""

import base64
import csv
import html
import json
import math
import shlex
from pathlib import Path

import numpy as np

from host.campaign.store import RESULTS
from host.core.errors import HarnessError

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
    """Failed runs first (by fault set, world, seed), then the passes ranked by the figure
    ``by`` (the highest first, or the lowest when ``low``)."""
    fails = sorted((r for r in results if not r["passed"]), key=lambda r: (r["faultset"], r["world"], r["seed"]))

    def badness(r):
        v = r["figures"].get(by, math.nan) if by else math.nan
        return -math.inf if math.isnan(v) else (-v if low else v)

    passes = sorted((r for r in results if r["passed"]), key=badness, reverse=True)
    return (fails + passes)[:n]


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
    except Exception as e:  # the report is derived data: say so, name what is kept
        first = (str(e).strip().splitlines() or [""])[0][:200]
        raise ReportError(
            f"the report in {out} was not written ({type(e).__name__}: {first}); the {len(results)} results are "
            f"kept in {out / RESULTS}: the same command writes the report again without running them"
        ) from e


def _write_report(out: Path, campaign: dict, results: list[dict]) -> dict:
    rows = summarize(results)
    worst_runs = worst(results, campaign.get("worst_by"), campaign.get("worst_low", False))
    for r in worst_runs:
        r["replay"] = replay_command(out, r["key"])
    summary = {"campaign": campaign, "groups": rows, "worst": worst_runs, "runs": len(results)}
    (out / "summary.json").write_text(json.dumps(summary, indent=1, default=str) + "\n", encoding="utf-8")
    _write_group_csv(out / "summary.csv", rows)
    _write_runs_csv(out / "runs.csv", results)
    plots = _plots(out / "plots", results, rows)
    page = out / "campaign.html"
    page.write_text(_html(campaign, rows, worst_runs, plots, len(results)), encoding="utf-8")
    return {"html": page, "json": out / "summary.json", "csv": out / "summary.csv", "runs_csv": out / "runs.csv"}


def _write_group_csv(path: Path, rows: list[dict]) -> None:
    names = sorted({f for r in rows for f in r["figures"]})
    with path.open("w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        head = ["faultset", "world", "runs", "passed", "rate", "wilson_lo", "wilson_hi"]
        w.writerow(head + [f"{n}_{q}" for n in names for q in ("p5", "median", "p95")])
        for r in rows:
            figs = [r["figures"].get(n, {}).get(q, "") for n in names for q in ("p5", "median", "p95")]
            w.writerow([r[h] for h in head] + figs)


def _write_runs_csv(path: Path, results: list[dict]) -> None:
    names = sorted({f for r in results for f in r["figures"]})
    with path.open("w", newline="", encoding="utf-8") as f:
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

    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    labels = [f"{r['faultset']} / {r['world']}" for r in rows]
    fig, ax = plt.subplots(figsize=(7, 0.5 + 0.45 * len(rows)))
    rates = [r["rate"] for r in rows]
    ax.errorbar(rates, range(len(rows)), xerr=error_bars(rows), fmt="o", capsize=4)
    ax.set_yticks(range(len(rows)), labels)
    ax.set_xlim(-0.02, 1.02)
    ax.set_xlabel("success rate (95 % Wilson interval)")
    fig.tight_layout()
    paths.append(_save(fig, folder / "success_rate.png"))
    names = sorted({f for r in results for f in r["figures"]}) + ["wall_s"]
    for name in names:
        fig, ax = plt.subplots(figsize=(7, 3.2))
        series = []
        for (faultset, world), label in zip(((r["faultset"], r["world"]) for r in rows), labels):
            values = [
                (r["figures"].get(name) if name != "wall_s" else r.get("wall_s"))
                for r in results
                if (r["faultset"], r["world"]) == (faultset, world)
            ]
            series.append(([v for v in values if v is not None and math.isfinite(v)], label))
        every = [v for values, _ in series for v in values]
        if every:  # the same bins for every group, so their bars compare
            bins = np.histogram_bin_edges(every, bins=min(30, max(5, len(every) // 3)))
            for values, label in series:
                if values:
                    ax.hist(values, bins=bins, alpha=0.6, label=label)
        ax.set_xlabel(name)
        ax.set_ylabel("runs")
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize="small")
        fig.tight_layout()
        paths.append(_save(fig, folder / f"{name}.png"))
    return paths


def _save(fig, path: Path) -> Path:
    import matplotlib.pyplot as plt

    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path


def _html(campaign: dict, rows: list[dict], worst_runs: list[dict], plots: list[Path], n: int) -> str:
    e = html.escape
    names = sorted({f for r in rows for f in r["figures"]})
    head = "".join(f"<th>{e(x)} (median, 5-95 %)</th>" for x in names)
    body = []
    for r in rows:
        figs = "".join(
            f"<td>{_num(r['figures'][x]['median'])} ({_num(r['figures'][x]['p5'])}-{_num(r['figures'][x]['p95'])})</td>"
            if x in r["figures"]
            else "<td></td>"
            for x in names
        )
        errors = ", ".join(f"{k} {v}" for k, v in r["errors"].items())
        body.append(
            f"<tr><td>{e(r['faultset'])}</td><td>{e(r['world'])}</td><td>{r['passed']} / {r['runs']}</td>"
            f"<td>{r['rate']:.0%} [{r['wilson_lo']:.0%}, {r['wilson_hi']:.0%}]</td><td>{e(errors)}</td>{figs}</tr>"
        )
    worst_rows = "".join(
        f"<tr><td>{'pass' if r['passed'] else '<b>FAIL</b>'}</td><td>{e(r['faultset'])}</td><td>{e(r['world'])}</td>"
        f"<td>{r['seed']}</td><td>{e(', '.join(f'{k}={_num(v)}' for k, v in r['figures'].items()))}</td>"
        f"<td><pre>{e((r.get('message') or '')[:600])}</pre></td><td><code>{e(r['replay'])}</code></td></tr>"
        for r in worst_runs
    )
    images = "".join(
        f'<figure><img alt="{e(p.stem)}" src="data:image/png;base64,{base64.b64encode(p.read_bytes()).decode()}">'
        f"<figcaption>{e(p.stem)}</figcaption></figure>"
        for p in plots
    )
    setup = e(json.dumps({k: v for k, v in campaign.items() if k != "faultsets"}, default=str))
    faultsets = e(json.dumps(campaign.get("faultsets", {}), default=str, indent=1))
    return f"""<!doctype html><html><head><meta charset="utf-8"><title>campaign {e(str(campaign.get("name")))}</title>
<style>body{{font-family:sans-serif;margin:1.5em}}table{{border-collapse:collapse}}td,th{{border:1px solid #ccc;
padding:3px 6px;font-size:13px;vertical-align:top}}pre{{margin:0;white-space:pre-wrap;max-width:40em}}
figure{{display:inline-block;margin:6px}}</style></head><body>
<h1>Campaign {e(str(campaign.get("name")))}: {n} runs</h1>
<p>rig <code>{e(str(campaign.get("rig")))}</code>; <a href="summary.csv">summary.csv</a>,
<a href="runs.csv">runs.csv</a>, <a href="summary.json">summary.json</a>, <a href="results.jsonl">results.jsonl</a></p>
<h2>Success by fault set and world</h2>
<table><tr><th>fault set</th><th>world</th><th>passed</th><th>rate [95 % Wilson]</th><th>errors</th>{head}</tr>
{"".join(body)}</table>
<h2>Worst runs</h2>
<table><tr><th></th><th>fault set</th><th>world</th><th>seed</th><th>figures</th><th>message</th><th>replay</th></tr>
{worst_rows}</table>
<h2>Distributions</h2>{images}
<h2>Set-up</h2><pre>{setup}</pre><pre>{faultsets}</pre>
</body></html>
"""


def _num(v) -> str:
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "-"
    return f"{v:.3g}"
