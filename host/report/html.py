"""The HTML report of a HIL session: a page with a row per scenario (its result, the
verdict of each of its timing budgets, its plots), grouped by app, and the tests that
were skipped with their reasons.

The page needs nothing but itself and the plots beside it: inline CSS, no script, the
system's fonts; its images and the links to the artefacts folders are files, relative
to the report (so the page stays small however many plots it shows). It reads at any
width from a phone's to 2560 px: tables fit their container (on a narrow screen each
row becomes a card), long names wrap.
"""

import html
import json
import os
from dataclasses import dataclass, field
from pathlib import Path

from host.artefacts.checks import partial_reason
from host.core import provenance, safefs
from host.rig.config import verdicts

BUDGET_COLUMNS = ("budget", "limit", "count", "p50", "p95", "p99", "max", "misses", "verdict")
PLOT_TITLES = {
    "trajectory": "trajectory",
    "timing": "timing budgets",
    "signals": "signals over time",
    "cpu": "the firmware's CPU load (MCU time)",
}
"""Plots in the order the report shows them: the first two side by side, then the rest
full width."""
NO_APP = "tests without a rig"


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

    @property
    def app(self) -> str:
        """The app its first recorded rig ran (the report's group; a board of a set, the set:
        ``two_board_rover`` for ``two_board_rover.nav``), else its test module's name."""
        for rig in self.rigs:
            if rig.header and rig.header.get("app"):
                board = (rig.header.get("spec") or {}).get("app", "").rpartition("::")[2]
                if "wired" in rig.header and board:  # (host/artefacts/folder.py: a board of a set's header)
                    return rig.header["app"].removesuffix(f".{board}")
                return rig.header["app"]
        return self.nodeid.split("::")[0].rsplit("/", 1)[-1].removesuffix(".py") if self.rigs else NO_APP


def write_report(
    path,
    scenarios: list[Scenario],
    *,
    micropython: str = "",
    title: str = "HIL report",
    totals: dict | None = None,
    skipped: list[tuple[str, str]] = (),
    coverage: dict | None = None,
) -> Path:
    path = Path(path)
    safefs.make_folder(path.parent)  # (its folder a link: refused)
    text = render(scenarios, base=path.parent, micropython=micropython, title=title, totals=totals, skipped=skipped)
    if coverage:
        text = text.replace("</header>", coverage_line(coverage, path.parent) + "</header>", 1)
    safefs.write_text(path, text)  # (a link at its name replaced, never written through)
    return path


def render(
    scenarios: list[Scenario],
    *,
    base: Path,
    micropython: str = "",
    title: str = "HIL report",
    totals: dict | None = None,
    skipped: list[tuple[str, str]] = (),
) -> str:
    """``totals``: outcome -> count over the whole session (as pytest counts); without it,
    the scenarios shown are counted. ``skipped``: (test, reason) of each skipped test."""
    counts: dict[str, int] = dict(totals or {})
    if totals is None:
        for s in scenarios:
            counts[s.outcome] = counts.get(s.outcome, 0) + 1
    verdict = "failed" if counts.get("failed") or counts.get("error") else "passed"
    summary = ", ".join(f"{n} {outcome}" for outcome, n in sorted(counts.items())) or "no scenarios"
    if totals is not None:
        summary += f"; {len(scenarios)} scenario(s) with their rigs below"
    rows = [b for s in scenarios for r in s.rigs for b in r.budgets if "budget" in b and b["budget"] != "(plots)"]
    budget_class, budget_line = verdicts.headline(rows)
    groups = grouped(scenarios)
    parts = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        f"<title>{_e(title)}: {_e(summary)}</title>",
        f"<style>{CSS}</style></head><body>",
        f'<header><h1>{_e(title)}</h1><p class="verdict {verdict}" id="summary">{_e(summary)}</p>',
        f'<p class="verdict {budget_class}" id="budgets">{_e(budget_line)}</p>',
        f"<p>commit <code>{_e(provenance.commit())}</code>"
        + (f" · MicroPython <code>{_e(micropython)}</code>" if micropython else "")
        + "</p>",
        _contents(groups, skipped),
        "</header>",
        _overview(groups),
    ]
    for app, members in groups.items():
        parts.append(f'<h2 class="app" id="{_app_id(app)}">{_e(app)} <small>{_tally(members)}</small></h2>')
        parts += [_scenario(i, s, base) for i, s in members]
    parts.append(_skipped(skipped))
    parts.append("</body></html>\n")
    return "\n".join(parts)


def coverage_line(coverage: dict, base: Path) -> str:
    """The firmware's coverage in the header: its total, linked to its HTML (docs/coverage.md)."""
    if "total" not in coverage:
        return f'<p id="coverage">firmware coverage: none ({_e(coverage.get("error", ""))})</p>'
    html, data = Path(coverage["html"]), Path(coverage["data"])
    href = os.path.relpath(html, base)
    return (
        f'<p id="coverage">firmware coverage <a href="{_e(href)}">{coverage["total"]:.0f}% of lines and branches</a>'
        f" · data <code>{_e(str(data))}</code> (<code>coverage report --data-file=…</code>)</p>"
    )


def grouped(scenarios: list[Scenario]) -> dict[str, list[tuple[int, Scenario]]]:
    """Scenarios by app (apps by name, tests without a rig last), each app's in the
    order of their test ids (a module's tests in file order), with their index."""
    groups: dict[str, list[tuple[int, Scenario]]] = {}
    for i, s in enumerate(scenarios):
        groups.setdefault(s.app, []).append((i, s))
    ordered = sorted(groups, key=lambda app: (app == NO_APP, app))
    return {app: sorted(groups[app], key=lambda pair: pair[1].nodeid) for app in ordered}


def _tally(members: list[tuple[int, Scenario]]) -> str:
    found: dict[str, int] = {}
    for _, s in members:
        found[s.outcome] = found.get(s.outcome, 0) + 1
    return _e(", ".join(f"{n} {outcome}" for outcome, n in sorted(found.items())))


def _app_id(app: str) -> str:
    return "app-" + "".join(c if c.isalnum() else "-" for c in app)


def _contents(groups: dict, skipped) -> str:
    links = [f'<a href="#{_app_id(app)}">{_e(app)}</a> ({len(members)})' for app, members in groups.items()]
    if skipped:
        links.append(f'<a href="#skipped">skipped</a> ({len(skipped)})')
    return f"<nav><b>apps:</b> {' · '.join(links)}</nav>" if links else ""


def _overview(groups: dict[str, list[tuple[int, Scenario]]]) -> str:
    labels = ("scenario", "result", "rigs", "virtual time", "wall time", "budgets", "what it measured")
    rows = []
    for app, members in groups.items():
        rows.append(f'<tr class="group"><th colspan="{len(labels)}">{_e(app)}</th></tr>')
        for i, s in members:
            t_end = [r.header["t_end_us"] / 1e6 for r in s.rigs if r.header]
            cells = (
                f'<a href="#s{i}">{_e(s.name)}</a>',
                f'<span class="badge {s.outcome}">{_e(s.outcome)}</span>',
                str(len(s.rigs)),
                f"{sum(t_end):g} s" if t_end else "-",
                f"{s.duration_s:.2f} s",
                _verdict_tally([b for r in s.rigs for b in r.budgets if b.get("budget") != "(plots)"]),
                _e(s.result),
            )
            tds = "".join(
                f'<td data-label="{label}"{" class=n" if 0 < k < 5 else ""}>{cell}</td>'
                for k, (label, cell) in enumerate(zip(labels, cells))
            )
            rows.append(f'<tr class="{s.outcome}">{tds}</tr>')
    head = "".join(f"<th>{label}</th>" for label in labels)
    return f'<table class="overview"><thead><tr>{head}</tr></thead><tbody>{"".join(rows)}</tbody></table>'


def _verdict_tally(rows: list[dict]) -> str:
    """A scenario's budgets by verdict (``3 held``, ``1 tolerated``), the misses named
    with why."""
    if not rows:
        return "-"
    tally = " ".join(f'<span class="v {v}">{n} {v}</span>' for v, n in verdicts.counts(rows).items())
    notes = [
        f'<span class="why">{_e(r["budget"])} {r["misses"]}/{r["count"]}: {_e(r.get("why", ""))}</span>'
        for r in rows
        if verdicts.verdict_of(r) in (verdicts.MISSED, verdicts.TOLERATED)
    ]
    return tally + "".join(notes)


def _scenario(i: int, s: Scenario, base: Path) -> str:
    out = [
        f'<section class="scenario {s.outcome}" id="s{i}">',
        f'<h3><span class="badge {s.outcome}">{_e(s.outcome)}</span> {_e(s.name)}</h3>',
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
            out.append(_plots(rig, base))
        out += _longest_compute(rig)
        out.append("</details>")
    out.append("</section>")
    return "\n".join(out)


def _plots(rig: RigResult, base: Path) -> str:
    out = ['<div class="plots">']
    order = list(PLOT_TITLES)
    for plot in sorted(rig.plots, key=lambda p: order.index(p.stem) if p.stem in order else len(order)):
        alt = PLOT_TITLES.get(plot.stem, plot.stem)
        img = f'<a href="{_e(_rel(plot, base))}"><img alt="{_e(alt)}" src="{_e(_rel(plot, base))}"></a>'
        out.append(f'<figure class="{_e(plot.stem)}">{img}<figcaption>{_e(alt)}</figcaption></figure>')
    out.append("</div>")
    out += _displays(rig, base)
    movie = rig.plots[0].parent / "trajectory.gif"
    if movie.is_file():
        out.append(f'<p class="movie"><a href="{_e(_rel(movie, base))}">the run as a moving picture (GIF)</a></p>')
    return "\n".join(out)


def _longest_compute(rig: RigResult) -> list[str]:
    """With MCU time: the longest compute stretches between two waits, each with the code
    that ran its largest piece (docs/mcu-time.md), so that a missed budget names its function."""
    mcu = (rig.header or {}).get("mcu_time")
    if not isinstance(mcu, dict) or not mcu.get("longest"):
        return []
    out = [
        '<table class="longest-compute"><caption>the longest compute between two waits on '
        f"{_e(mcu.get('cpu', ''))}, with the code that ran its largest piece (innermost last)</caption>",
        "<tr><th>ends at (s)</th><th>compute (µs)</th><th>largest piece (µs)</th><th>code</th></tr>",
    ]
    for s in mcu["longest"]:
        code = s.get("code") or "(no frame of the firmware's)"
        out.append(
            f"<tr><td>{s['t_us'] / 1e6:.6f}</td><td>{s['compute_us']:,}</td><td>{s['piece_us']:,}</td>"
            f"<td><pre>{_e(code)}</pre></td></tr>"
        )
    out.append("</table>")
    return out


def _displays(rig: RigResult, base: Path) -> list[str]:
    """Each display part's last picture (``<name>.png`` of the trace folder), linked to
    all its pictures in turn (``<name>.gif``), and its film strip (``<name>.frames.png``,
    the header's ``displays``: a few of its pictures over the run, with their times)."""
    out = []
    strips = (rig.header or {}).get("displays") or {}
    for part in ((rig.header or {}).get("parts") or {}).get("parts", []):
        still, moving = rig.folder / f"{part.get('name')}.png", rig.folder / f"{part.get('name')}.gif"
        if part.get("kind") in ("ssd1306", "sh1106", "ht16k33", "st7789") and still.is_file():
            alt = f"{part['name']}: the display's last picture"
            img = f'<a href="{_e(_rel(moving, base))}"><img alt="{_e(alt)}" src="{_e(_rel(still, base))}"></a>'
            out.append(
                f'<figure class="display">{img}<figcaption>{_e(alt)} (all of them: the GIF)</figcaption></figure>'
            )
            strip = strips.get(part["name"]) or {}
            film = rig.folder / str(strip.get("strip", ""))
            if strip.get("strip") and film.is_file():
                times = ", ".join(f"{t / 1e6:.3f}" for t in strip.get("strip_t_us", []))
                alt = f"{part['name']}: {len(strip.get('strip_t_us', []))} of its {strip.get('frames')} pictures"
                img = f'<img alt="{_e(alt)}" src="{_e(_rel(film, base))}">'
                out.append(
                    f'<figure class="display-frames">{img}<figcaption>{_e(alt)}, shown from {_e(times)} s'
                    "</figcaption></figure>"
                )
    return out


def _rig_title(rig: RigResult) -> str:
    h = rig.header
    if not h:
        return _e(rig.label)
    world = (h.get("world") or {}).get("name", "")
    text = f"{rig.label}: {h['app']} on {h['board']}, {world}, seed {h['seed']}, {h['mode']}, {h['t_end_us'] / 1e6:g} s"
    given = parameters(h)
    if given:
        text += f"; {given}"
    partial = partial_reason(h)
    console = h.get("console") or {}
    if partial:
        text += f"; partial: {partial}"
    if console.get("dropped_bytes"):
        text += f"; console.log capped: {console['dropped_bytes']} bytes in {console['dropped_lines']} lines dropped"
    return _e(text)


def parameters(header: dict) -> str:
    """What the test gave the rig beyond its app's own settings (the spec's options but
    the world, shown already; its faults and placement): ``link.script=[[0, "K 25"]]``."""
    spec = header.get("spec") or {}
    given = {k: v for k, v in (spec.get("options") or {}).items() if k != "world"}
    for key in ("faults", "placement"):
        if spec.get(key):
            given[key] = spec[key]
    return ", ".join(f"{k}={_compact(v)}" for k, v in given.items())


def _compact(value) -> str:
    return value if isinstance(value, str) else json.dumps(value, separators=(", ", ": "))


def _budget_table(rows: list[dict]) -> str:
    head = "".join(f"<th>{c}</th>" for c in BUDGET_COLUMNS)
    body = []
    for row in rows:
        cells = []
        verdict = verdicts.verdict_of(row) if "count" in row else ""
        for c in BUDGET_COLUMNS:
            value = row.get(c)
            if c == "verdict" and verdict:
                why = f'<span class="why">{_e(row.get("why", ""))}</span>' if row.get("why") else ""
                cell = f'<span class="v {verdict}">{verdict}</span>{why}'
            else:
                cell = "-" if value is None else _e(str(value))
            cls = f' class="{verdict}"' if c == "misses" and value and verdict else ""
            cells.append(f'<td data-label="{c}"{cls}>{cell}</td>')
        body.append(f'<tr class="{verdict}">{"".join(cells)}</tr>')
    return f'<table class="budgets"><thead><tr>{head}</tr></thead><tbody>{"".join(body)}</tbody></table>'


def _skipped(skipped: list[tuple[str, str]]) -> str:
    if not skipped:
        return ""
    items = "".join(f"<li><code>{_e(test)}</code>: {_e(reason)}</li>" for test, reason in skipped)
    return f'<div class="skipped-list" id="skipped"><h2>skipped ({len(skipped)})</h2><ul>{items}</ul></div>'


def _rel(path: Path, base: Path) -> str:
    try:
        return Path(os.path.relpath(path, base)).as_posix()
    except ValueError:
        return Path(path).as_posix()


def _e(text) -> str:
    return html.escape(str(text), quote=True)


GREEN, AMBER, RED, GREY = "#2e7d32", "#b26a00", "#c62828", "#607d8b"
CSS = f"""
body {{ font-family: system-ui, -apple-system, "Segoe UI", "DejaVu Sans", sans-serif; margin: 1.2rem auto;
       max-width: 2400px; padding: 0 clamp(0.5rem, 2vw, 2rem); color: #1c2329; background: #fafafa; }}
a, code, summary, h3, .why, td {{ overflow-wrap: anywhere; }}
td.n, th {{ white-space: nowrap; overflow-wrap: normal; }}
h1 {{ margin-bottom: 0.2rem; }}
code {{ font-family: ui-monospace, "DejaVu Sans Mono", monospace; font-size: 0.9em; }}
.verdict {{ font-size: 1.15rem; font-weight: 600; margin: 0.3rem 0; }}
.verdict.passed, .verdict.held {{ color: {GREEN}; }} .verdict.failed, .verdict.missed {{ color: {RED}; }}
.verdict.tolerated {{ color: {AMBER}; }}
nav {{ margin: 0.4rem 0; line-height: 1.6; }}
table {{ border-collapse: collapse; margin: 0.6rem 0; font-size: 0.9rem; background: #fff; max-width: 100%; }}
th, td {{ border: 1px solid #cfd8dc; padding: 0.25rem 0.6rem; text-align: left; vertical-align: top; }}
th {{ background: #eceff1; }}
tr.group th {{ background: #cfd8dc; font-size: 1rem; }}
.overview {{ width: 100%; }}
.overview td:first-child {{ min-width: 16rem; width: 24%; }} .overview td:last-child {{ min-width: 18rem; }}
.overview td:nth-child(6) {{ min-width: 9rem; }}
.v {{ display: inline-block; border-radius: 4px; padding: 0 0.4rem; margin: 0 0.2rem 0.1rem 0; color: #fff;
      font-size: 0.85rem; font-weight: 600; background: {GREY}; white-space: nowrap; }}
.v.held {{ background: {GREEN}; }} .v.tolerated {{ background: {AMBER}; }} .v.missed {{ background: {RED}; }}
.why {{ display: block; font-size: 0.8rem; color: #455a64; }}
td.missed {{ color: {RED}; font-weight: 700; }} td.tolerated {{ color: {AMBER}; font-weight: 700; }}
table.budgets td[data-label="verdict"] {{ min-width: 12rem; }}
.badge {{ display: inline-block; border-radius: 4px; padding: 0.05rem 0.5rem; color: #fff; font-size: 0.85rem;
         font-weight: 600; vertical-align: middle; background: {GREY}; }}
.badge.passed {{ background: {GREEN}; }} .badge.failed, .badge.error {{ background: {RED}; }}
.badge.skipped {{ background: #9e9e9e; }}
h2.app {{ margin-top: 2rem; border-bottom: 2px solid #cfd8dc; }} h2.app small {{ font-weight: 400; color: #546e7a; }}
section.scenario {{ background: #fff; border: 1px solid #cfd8dc; border-left: 6px solid {GREY};
                   border-radius: 4px; margin: 1.2rem 0; padding: 0.4rem 1rem 0.8rem; }}
section.scenario.passed {{ border-left-color: {GREEN}; }}
section.scenario.failed, section.scenario.error {{ border-left-color: {RED}; }}
h3 {{ font-size: 1.1rem; }}
.nodeid, .where {{ color: #546e7a; font-size: 0.85rem; margin: 0.2rem 0; }}
pre.message {{ background: #fff3f3; border: 1px solid #f5c6c6; padding: 0.6rem; overflow-x: auto;
              font-size: 0.8rem; white-space: pre-wrap; }}
details {{ margin: 0.6rem 0; }} summary {{ cursor: pointer; font-weight: 600; }}
.plots {{ display: grid; grid-template-columns: repeat(auto-fit, minmax(min(420px, 100%), 1fr)); gap: 0.8rem; }}
figure {{ margin: 0; min-width: 0; }} figure.signals, figure.cpu {{ grid-column: 1 / -1; }}
table.longest-compute pre {{ margin: 0; font-size: 0.8rem; white-space: pre-wrap; }}
figure img {{ width: 100%; height: auto; border: 1px solid #eceff1; background: #fff; }}
figure.display img {{ width: min(100%, 512px); image-rendering: pixelated; }}  /* (a 128 x 64 screen at 4x) */
figure.display-frames img {{ width: 100%; image-rendering: pixelated; }}  /* (a film strip) */
@media (min-width: 1800px) {{ figure.signals {{ grid-column: auto; }} }}
figcaption {{ font-size: 0.8rem; color: #546e7a; text-align: center; }}
@media (max-width: 760px) {{
  table, thead, tbody, tr, th, td {{ display: block; }} table {{ width: 100%; }}
  thead {{ display: none; }}
  tr {{ border: 1px solid #cfd8dc; margin-bottom: 0.5rem; background: #fff; }}
  tr.group th {{ border: 0; }}
  td, td.n {{ border: 0; border-bottom: 1px solid #eceff1; min-width: 0 !important; width: auto !important;
             white-space: normal; }}
  td[data-label]::before {{ content: attr(data-label) ": "; color: #546e7a; font-weight: 600; }}
  section.scenario {{ padding: 0.3rem 0.5rem 0.6rem; }}
}}
"""
