"""One self-contained HTML report of a HIL session: a row per scenario with its result,
its budget table and its plots.

The page needs nothing but itself: inline CSS, no script, the system's fonts, plots
embedded as ``data:`` URIs. Links to the artefacts folders are relative to the report.
"""

import base64
import html
import os
from dataclasses import dataclass, field
from pathlib import Path

from host.artefacts.checks import partial_reason
from host.core import provenance

BUDGET_COLUMNS = ("budget", "limit", "count", "p50", "p95", "p99", "max", "misses")
PLOT_TITLES = {"trajectory": "trajectory", "timing": "timing budgets", "signals": "signals over time"}
"""Plots in the order the report shows them: the first two side by side, then the rest
full width."""


@dataclass
class RigResult:
    """One rig of a scenario: its trace folder, budget rows and plot files."""

    label: str
    folder: Path
    budgets: list[dict] = field(default_factory=list)
    plots: list[Path] = field(default_factory=list)
    header: dict | None = None


@dataclass
class Scenario:
    name: str
    nodeid: str
    outcome: str  # passed, failed, skipped, error
    duration_s: float = 0.0
    message: str = ""
    rigs: list[RigResult] = field(default_factory=list)
    result: str = ""  # what the test measured: record_property("result", text)


def write_report(
    path, scenarios: list[Scenario], *, micropython: str = "", title: str = "HIL report", totals: dict | None = None
) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    text = render(scenarios, base=path.parent, micropython=micropython, title=title, totals=totals)
    path.write_text(text, encoding="utf-8")
    return path


def render(
    scenarios: list[Scenario],
    *,
    base: Path,
    micropython: str = "",
    title: str = "HIL report",
    totals: dict | None = None,
) -> str:
    """``totals``: outcome -> count over the whole session (as pytest counts); without it,
    the scenarios shown are counted."""
    counts: dict[str, int] = dict(totals or {})
    if totals is None:
        for s in scenarios:
            counts[s.outcome] = counts.get(s.outcome, 0) + 1
    verdict = "failed" if counts.get("failed") or counts.get("error") else "passed"
    summary = ", ".join(f"{n} {outcome}" for outcome, n in sorted(counts.items())) or "no scenarios"
    if totals is not None:
        summary += f"; {len(scenarios)} scenario(s) with their rigs below"
    parts = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        f"<title>{_e(title)}: {_e(summary)}</title>",
        f"<style>{CSS}</style></head><body>",
        f'<header><h1>{_e(title)}</h1><p class="verdict {verdict}" id="summary">{_e(summary)}</p>',
        f"<p>commit <code>{_e(provenance.commit())}</code>"
        + (f" · MicroPython <code>{_e(micropython)}</code>" if micropython else "")
        + "</p></header>",
        _overview(scenarios),
    ]
    parts += [_scenario(i, s, base) for i, s in enumerate(scenarios)]
    parts.append("</body></html>\n")
    return "\n".join(parts)


def _overview(scenarios: list[Scenario]) -> str:
    rows = []
    for i, s in enumerate(scenarios):
        t_end = [r.header["t_end_us"] / 1e6 for r in s.rigs if r.header]
        virtual = f"{sum(t_end):g} s" if t_end else "-"
        misses = sum(b.get("misses") or 0 for r in s.rigs for b in r.budgets if "wall" not in str(b.get("limit")))
        rows.append(
            f'<tr class="{s.outcome}"><td><a href="#s{i}">{_e(s.name)}</a></td>'
            f'<td><span class="badge {s.outcome}">{_e(s.outcome)}</span></td>'
            f"<td>{len(s.rigs)}</td><td>{virtual}</td><td>{s.duration_s:.2f} s</td>"
            f'<td class="{"miss" if misses else ""}">{misses}</td><td>{_e(s.result)}</td></tr>'
        )
    head = "<tr><th>scenario</th><th>result</th><th>rigs</th><th>virtual time</th><th>wall time</th>"
    head += "<th>budget misses (enforced)</th><th>what it measured</th></tr>"
    return f'<table class="overview"><thead>{head}</thead><tbody>{"".join(rows)}</tbody></table>'


def _scenario(i: int, s: Scenario, base: Path) -> str:
    out = [
        f'<section class="scenario {s.outcome}" id="s{i}">',
        f'<h2><span class="badge {s.outcome}">{_e(s.outcome)}</span> {_e(s.name)}</h2>',
        f'<p class="nodeid"><code>{_e(s.nodeid)}</code> · {s.duration_s:.2f} s wall</p>',
    ]
    if s.result:
        out.append(f'<p class="result"><b>measured:</b> {_e(s.result)}</p>')
    if s.message:
        out.append(f'<pre class="message">{_e(s.message)}</pre>')
    for n, rig in enumerate(s.rigs):
        out.append(f"<details{' open' if n == 0 else ''}><summary>{_rig_title(rig)}</summary>")
        out.append(f'<p class="where">artefacts: <a href="{_e(_rel(rig.folder, base))}">{_e(str(rig.folder))}</a></p>')
        if rig.budgets:
            out.append(_budget_table(rig.budgets))
        if rig.plots:
            out.append('<div class="plots">')
            order = list(PLOT_TITLES)
            for plot in sorted(rig.plots, key=lambda p: order.index(p.stem) if p.stem in order else len(order)):
                alt = PLOT_TITLES.get(plot.stem, plot.stem)
                img = f'<img alt="{_e(alt)}" src="{_data_uri(plot)}">'
                out.append(f'<figure class="{_e(plot.stem)}">{img}<figcaption>{_e(alt)}</figcaption></figure>')
            out.append("</div>")
            movie = rig.plots[0].parent / "trajectory.gif"
            if movie.is_file():
                out.append(
                    f'<p class="movie"><a href="{_e(_rel(movie, base))}">the run as a moving picture (GIF)</a></p>'
                )
        out.append("</details>")
    out.append("</section>")
    return "\n".join(out)


def _rig_title(rig: RigResult) -> str:
    h = rig.header
    if not h:
        return _e(rig.label)
    world = (h.get("world") or {}).get("name", "")
    text = f"{rig.label}: {h['app']} on {h['board']}, {world}, seed {h['seed']}, {h['mode']}, {h['t_end_us'] / 1e6:g} s"
    partial = partial_reason(h)
    console = h.get("console") or {}
    if partial:
        text += f"; partial: {partial}"
    if console.get("dropped_bytes"):
        text += f"; console.log capped: {console['dropped_bytes']} bytes in {console['dropped_lines']} lines dropped"
    return _e(text)


def _budget_table(rows: list[dict]) -> str:
    head = "".join(f"<th>{c}</th>" for c in BUDGET_COLUMNS)
    body = []
    for row in rows:
        cells = []
        for c in BUDGET_COLUMNS:
            value = row.get(c)
            cls = ' class="miss"' if c == "misses" and value else ""
            cells.append(f"<td{cls}>{'-' if value is None else _e(str(value))}</td>")
        body.append(f"<tr>{''.join(cells)}</tr>")
    return f'<table class="budgets"><thead><tr>{head}</tr></thead><tbody>{"".join(body)}</tbody></table>'


def _data_uri(path: Path) -> str:
    return "data:image/png;base64," + base64.b64encode(Path(path).read_bytes()).decode("ascii")


def _rel(path: Path, base: Path) -> str:
    try:
        return Path(os.path.relpath(path, base)).as_posix()
    except ValueError:
        return Path(path).as_posix()


def _e(text) -> str:
    return html.escape(str(text), quote=True)


CSS = """
body { font-family: system-ui, -apple-system, "Segoe UI", "DejaVu Sans", sans-serif; margin: 1.5rem auto;
       max-width: 1100px; padding: 0 1rem; color: #1c2329; background: #fafafa; }
h1 { margin-bottom: 0.2rem; }
code { font-family: ui-monospace, "DejaVu Sans Mono", monospace; font-size: 0.9em; }
.verdict { font-size: 1.2rem; font-weight: 600; }
.verdict.passed { color: #2e7d32; } .verdict.failed { color: #c62828; }
table { border-collapse: collapse; margin: 0.6rem 0; font-size: 0.9rem; background: #fff; }
th, td { border: 1px solid #cfd8dc; padding: 0.25rem 0.6rem; text-align: left; }
th { background: #eceff1; }
td.miss { color: #c62828; font-weight: 700; }
.overview { width: 100%; }
.badge { display: inline-block; border-radius: 4px; padding: 0.05rem 0.5rem; color: #fff; font-size: 0.85rem;
         font-weight: 600; vertical-align: middle; background: #607d8b; }
.badge.passed { background: #2e7d32; } .badge.failed, .badge.error { background: #c62828; }
.badge.skipped { background: #9e9e9e; }
section.scenario { background: #fff; border: 1px solid #cfd8dc; border-left: 6px solid #607d8b;
                   border-radius: 4px; margin: 1.2rem 0; padding: 0.4rem 1rem 0.8rem; }
section.scenario.passed { border-left-color: #2e7d32; }
section.scenario.failed, section.scenario.error { border-left-color: #c62828; }
h2 { font-size: 1.1rem; }
.nodeid, .where { color: #546e7a; font-size: 0.85rem; margin: 0.2rem 0; }
pre.message { background: #fff3f3; border: 1px solid #f5c6c6; padding: 0.6rem; overflow-x: auto;
              font-size: 0.8rem; white-space: pre-wrap; }
details { margin: 0.6rem 0; } summary { cursor: pointer; font-weight: 600; }
.plots { display: grid; grid-template-columns: repeat(auto-fit, minmax(420px, 1fr)); gap: 0.8rem; }
figure { margin: 0; } figure.signals { grid-column: 1 / -1; }
figure img { width: 100%; height: auto; border: 1px solid #eceff1; background: #fff; }
figcaption { font-size: 0.8rem; color: #546e7a; text-align: center; }
"""
