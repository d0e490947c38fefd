"""The campaign's HTML page (``campaign.html``), in the HIL report's house style (its CSS,
:data:`host.report.html.CSS`, with a few rules of the page's own): the verdict per
group, the success table, the worst runs by the judged figure (each with its figures,
its message, the command that replays it and, for a floor-covering robot, the map of
what it missed), the distributions and the set-up as tables. Images are files beside
the page (``plots/``, ``maps/``), linked relatively; no script, nothing remote."""

import html
import os
from pathlib import Path

from host.campaign.metrics import metric
from host.core import provenance
from host.report.html import CSS as HOUSE_CSS

CSS = (
    HOUSE_CSS
    + """
body { max-width: 1600px; }
table { max-width: 100%; }
td, th { overflow-wrap: break-word; vertical-align: top; }
.badge { white-space: nowrap; }
table.wide { width: 100%; }
td.num { text-align: right; white-space: nowrap; }
table.setup th { width: 40%; }
.plots { grid-template-columns: repeat(auto-fit, minmax(min(460px, 100%), 1fr)); }
.note { color: #546e7a; font-size: 0.9rem; }
p.group { margin: 0.3rem 0; font-size: 1.05rem; }
p.group .expected { color: #2e7d32; } p.group .unexpected { color: #c62828; font-weight: 600; }
section.scenario h3 { font-size: 1rem; margin: 0.5rem 0; }
section.scenario .run { display: grid; grid-template-columns: minmax(0, 1fr) minmax(0, 1.4fr); gap: 1rem; }
@media (max-width: 900px) { section.scenario .run { grid-template-columns: minmax(0, 1fr); } }
@media (max-width: 600px) { body { padding: 0 0.5rem; } table { font-size: 0.8rem; }
  th, td { padding: 0.2rem 0.3rem; } td.num { white-space: normal; }
  section.scenario { padding: 0.3rem 0.5rem 0.6rem; } }
code.replay { display: block; overflow-wrap: anywhere; white-space: pre-wrap; background: #f4f6f7; padding: 0.3rem; }
"""
)
SETUP = (
    ("rig", "rig"),
    ("judge", "judge"),
    ("worlds", "worlds"),
    ("seeds", "seeds"),
    ("seconds", "simulated seconds a run, at most"),
    ("until", "a run ends when the console shows"),
    ("step_s", "looks at the console every (s)"),
    ("timeout_s", "wall seconds before a run counts as hung"),
    ("budgets", "budgets a run must keep"),
    ("placement", "start pose error, drawn per seed"),
    ("figures", "truth fields recorded"),
)


def expectation(campaign: dict, row: dict) -> str:
    """For a showcase's group (``expected`` in its scenario file): whether its rate is the
    known one (inside this run's 95 % interval) and where that is explained; else ""."""
    rate = (campaign.get("expected") or {}).get(row["faultset"])
    if rate is None:
        return ""
    where = campaign.get("explained") or "docs/campaigns.md"
    if row["wilson_lo"] <= rate <= row["wilson_hi"]:
        return f"the expected showcase figure (about {rate:.0%}; explained in {where})"
    return f"NOT the showcase's expected {rate:.0%} (outside this interval; see {where})"


def render(
    campaign: dict, rows: list[dict], worst_runs: list[dict], plots: list[Path], maps: dict, n: int, judged: tuple
) -> str:
    """The page; ``judged``: the figure the runs are ranked by, and whether lowest is worst."""
    name = str(campaign.get("name"))
    by, low = judged
    groups = "".join(_group_line(campaign, r, expectation(campaign, r)) for r in rows)
    parts = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        f"<title>campaign {_e(name)}: {n} runs</title>",
        f"<style>{CSS}</style></head><body>",
        f"<header><h1>Campaign {_e(name)}: {n} runs</h1>{groups}",
        f'<p class="note">commit <code>{_e(provenance.commit())}</code> · rig <code>{_e(campaign.get("rig"))}</code>'
        ' · <a href="summary.csv">summary.csv</a> · <a href="runs.csv">runs.csv</a> · '
        '<a href="summary.json">summary.json</a> · <a href="results.jsonl">results.jsonl</a></p></header>',
        "<h2>Success by fault set and world</h2>",
        _success_table(rows),
        f"<h2>Worst runs, by {_e(metric(by).label)}</h2>",
        f'<p class="note">Failed runs first, then the passes; within each the {"lowest" if low else "highest"} '
        f"{_e(metric(by).label)} first (its worst). Each replays, traced, with the command shown.</p>",
        _worst_table(worst_runs, by),
        *[_worst_run(i, r, by, maps.get(r["key"])) for i, r in enumerate(worst_runs)],
        "<h2>Distributions</h2>",
        '<div class="plots">',
        *[_figure(p, p.parent.parent, _plot_title(p)) for p in plots],
        "</div>",
        "<h2>Set-up</h2>",
        _setup_table(campaign, by, low),
        _faultset_table(campaign.get("faultsets") or {}),
        "</body></html>\n",
    ]
    return "\n".join(parts)


def _group_line(campaign: dict, row: dict, note: str) -> str:
    verdict = "passed" if row["passed"] == row["runs"] else "failed"
    cls = "unexpected" if note.startswith("NOT") else "expected"
    text = (
        f"{row['faultset']} / {row['world']}: <b>{row['passed']} of {row['runs']} passed</b>, {row['rate']:.0%} "
        f"(95 % Wilson {row['wilson_lo']:.0%}–{row['wilson_hi']:.0%})"
    )
    note_html = f' — <span class="{cls}">{_e(note)}</span>' if note else ""
    return f'<p class="group"><span class="badge {verdict}">{verdict}</span> {text}{note_html}</p>'


def _success_table(rows: list[dict]) -> str:
    head = "<tr><th>fault set</th><th>world</th><th>passed</th><th>rate</th><th>95 % Wilson</th><th>errors</th></tr>"
    body = []
    for r in rows:
        errors = ", ".join(f"{k} {v}" for k, v in r["errors"].items()) or "none"
        body.append(
            f"<tr><td>{_e(r['faultset'])}</td><td>{_e(r['world'])}</td><td class=num>{r['passed']} / {r['runs']}</td>"
            f"<td class=num>{r['rate']:.0%}</td><td class=num>{r['wilson_lo']:.0%}–{r['wilson_hi']:.0%}</td>"
            f"<td>{_e(errors)}</td></tr>"
        )
    out = [f'<table class="wide success"><thead>{head}</thead><tbody>{"".join(body)}</tbody></table>']
    for r in rows:
        if r["figures"]:
            out.append(f"<h3>{_e(r['faultset'])} / {_e(r['world'])}: figures over {r['runs']} runs</h3>")
            out.append(_figures_table(r["figures"]))
    return "\n".join(out)


def _figures_table(figures: dict) -> str:
    body = []
    for name, q in sorted(figures.items(), key=lambda kv: metric(kv[0]).label):
        m = metric(name)
        better = "higher" if m.higher_is_better else "lower"
        body.append(
            f"<tr><td>{_e(m.label)}</td><td class=num>{_e(m.show(q['median']))}</td>"
            f"<td class=num>{_e(m.show(q['p5']))} – {_e(m.show(q['p95']))}</td><td>{better}</td></tr>"
        )
    head = "<tr><th>figure</th><th>median</th><th>5–95 %</th><th>better</th></tr>"
    return f'<table class="figures"><thead>{head}</thead><tbody>{"".join(body)}</tbody></table>'


def _worst_table(worst_runs: list[dict], by: str) -> str:
    m = metric(by)
    body = "".join(
        f'<tr><td class=num>{i + 1}</td><td><span class="badge {"passed" if r["passed"] else "failed"}">'
        f'{"pass" if r["passed"] else "fail"}</span></td><td><a href="#w{i}">{_e(r["key"])}</a></td>'
        f"<td class=num>{_e(m.show(r['figures'].get(by)))}</td></tr>"
        for i, r in enumerate(worst_runs)
    )
    head = f"<tr><th>#</th><th>result</th><th>run (fault set / world / seed)</th><th>{_e(m.title)}</th></tr>"
    return f'<table class="worst"><thead>{head}</thead><tbody>{body}</tbody></table>'


def _worst_run(i: int, r: dict, by: str, fmap) -> str:
    outcome = "passed" if r["passed"] else "failed"
    m = metric(by)
    figures = "".join(
        f"<tr><td>{_e(metric(k).label)}</td><td class=num>{_e(metric(k).show(v))}</td></tr>"
        for k, v in sorted(r["figures"].items(), key=lambda kv: (kv[0] != by, metric(kv[0]).label))
    )
    left = [
        f'<table class="figures"><thead><tr><th>figure</th><th>value</th></tr></thead><tbody>{figures}</tbody></table>'
        if figures
        else '<p class="note">no figures (the run ended in an error)</p>',
        f'<pre class="message">{_e(r.get("message"))}</pre>' if r.get("message") else "",
        f'<p class="where">replay, traced:</p><code class="replay">{_e(r.get("replay", ""))}</code>',
    ]
    right = ""
    if fmap is not None:
        base = fmap.image.parent.parent
        right = _figure(fmap.image, base, f"where it missed the floor: {fmap.caption()}")
    return (
        f'<section class="scenario {outcome}" id="w{i}"><h3><span class="badge {outcome}">'
        f"{'pass' if r['passed'] else 'fail'}</span> {i + 1}. {_e(r['key'])}: {_e(m.label)} "
        f'{_e(m.show(r["figures"].get(by)))}</h3><div class="run"><div>{"".join(left)}</div>'
        f"<div>{right}</div></div></section>"
    )


def _plot_title(path: Path) -> str:
    return "success rate by fault set and world" if path.stem == "success_rate" else metric(path.stem).title


def _figure(path: Path, base: Path, caption: str) -> str:
    src = Path(os.path.relpath(path, base)).as_posix()
    img = f'<img alt="{_e(caption)}" src="{_e(src)}">'
    return f"<figure>{img}<figcaption>{_e(caption)}</figcaption></figure>"


def _setup_table(campaign: dict, by: str, low: bool) -> str:
    rows = []
    for key, label in SETUP:
        value = campaign.get(key)
        if key == "seeds":
            first = campaign.get("first_seed", 1)
            value = f"{value}: {first} to {first + value - 1}" if isinstance(value, int) else value
        if value in (None, [], {}, ""):
            continue
        rows.append(f"<tr><th>{_e(label)}</th><td>{_e(_plain(value))}</td></tr>")
    ranked = f"{metric(by).label} ({'lowest' if low else 'highest'} first)"
    rows.append(f"<tr><th>worst runs ranked by</th><td>{_e(ranked)}</td></tr>")
    if campaign.get("source"):
        rows.append(f"<tr><th>scenario file</th><td><code>{_e(campaign['source'])}</code></td></tr>")
    return f'<table class="setup"><tbody>{"".join(rows)}</tbody></table>'


def _faultset_table(faultsets: dict) -> str:
    rows = []
    for name, faults in faultsets.items():
        if not faults:
            rows.append(f"<tr><td>{_e(name)}</td><td>none</td><td></td></tr>")
        for f in faults:
            fields = ", ".join(f"{k} = {_plain(v)}" for k, v in f.items() if k != "kind")
            rows.append(f"<tr><td>{_e(name)}</td><td>{_e(f.get('kind'))}</td><td>{_e(fields)}</td></tr>")
    head = "<tr><th>fault set</th><th>fault</th><th>its fields</th></tr>"
    return f'<table class="faultsets"><thead>{head}</thead><tbody>{"".join(rows)}</tbody></table>'


def _plain(value) -> str:
    """A setting as a reader writes it: lists comma-separated, tables as key = value."""
    if isinstance(value, dict):
        return ", ".join(f"{k} = {_plain(v)}" for k, v in value.items())
    if isinstance(value, (list, tuple)):
        return (
            ", ".join(_plain(v) for v in value)
            if not all(isinstance(v, (int, float)) for v in value)
            else ("[" + ", ".join(f"{v:g}" for v in value) + "]")
        )
    if isinstance(value, float):
        return f"{value:g}"
    return str(value) if not isinstance(value, str) else value


def _e(text) -> str:
    return html.escape("" if text is None else str(text), quote=True)


__all__ = ["render"]
