"""PNG plots of a trace folder (matplotlib, Agg canvas, no display, no pyplot state).

- ``trajectory.png``: the ground-truth path over the world's walls, coloured by time,
  on the floor it covered (or the floor's picture, a ``line_course``'s); start, end and
  every bump marked.
- ``signals.png``: sensors, estimate and actuator commands over virtual time
  (:mod:`host.report.views` chooses them per app).
- ``timing.png``: a histogram per timing budget against its limit.
- ``trajectory.gif``: the same path as a moving picture (:mod:`host.report.movie`).
"""

import textwrap
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection
from matplotlib.colors import ListedColormap
from matplotlib.figure import Figure
from matplotlib.ticker import FuncFormatter, NullLocator

from host.artefacts import integrity
from host.artefacts.folder import TraceData, load_trace
from host.core import safefs
from host.report import views
from host.rig.config import verdicts

DPI = 100
PLOTS = "plots"
OK_COLOUR = "#2e7d32"
MISS_COLOUR = "#c62828"
TOLERATED_COLOUR = "#b26a00"
INFO_COLOUR = "#607d8b"
LEGEND_WIDTH_IN = 2.3  # right of a signals panel: its legend, beside the lines rather than over them
LEGEND_CHARS = 32  # a longer label wraps (x-small letters: the legend's width holds this many)
COVERED_RGBA = (0.55, 0.80, 0.55, 1.0)
FREE_RGBA = (0.93, 0.93, 0.93, 1.0)


def plot_trace(folder, out_dir=None) -> list[Path]:
    """Write every plot of a trace folder into ``out_dir`` (default ``<folder>/plots``);
    returns the files written."""
    trace = load_trace(folder)
    out = safefs.make_folder(Path(out_dir) if out_dir else Path(folder) / PLOTS)  # (plots/ a link: refused)
    written = []
    drawers = (("trajectory", trajectory_figure), ("signals", signals_figure), ("timing", timing_figure))
    for name, draw in (*drawers, ("cpu", cpu_figure)):
        fig = draw(trace)
        if fig is not None:
            path = out / f"{name}.png"
            _save(fig, path)
            written.append(path)
    from host.report.movie import write_movie

    write_movie(trace, out / "trajectory.gif")  # (a link in the report, not one of its images)
    return written


def _save(fig: Figure, path: Path) -> None:
    FigureCanvasAgg(fig)
    with integrity.atomic(path) as part:  # (a full disk leaves no PNG cut short)
        fig.savefig(part, dpi=DPI, format="png")


def _title(trace: TraceData) -> str:
    h = trace.header
    world = (h.get("world") or {}).get("name", "no world")
    return f"{h['app']} on {h['board']}, {world}, seed {h['seed']}, {h['t_end_us'] / 1e6:g} s"


# -- trajectory ------------------------------------------------------------------------


def trajectory_figure(trace: TraceData) -> Figure | None:
    tr = trace.truth
    if "x_m" not in tr or len(tr["x_m"]) == 0:
        return None
    world = trace.header.get("world")
    aspect = 0.75
    if world:
        seg = np.asarray(world["segments"], dtype=float)
        span = np.ptp(seg[:, [0, 2]]), np.ptp(seg[:, [1, 3]])
        aspect = span[1] / span[0] if span[0] > 0 else aspect
    height_in = min(max(6.2 * aspect + 1.6, 4.0), 10.0)
    fig = Figure(figsize=(8, height_in))  # fixed margins: a constrained layout costs half the drawing
    ax = fig.add_axes((0.09, 0.75 / height_in, 0.76, 1 - 1.45 / height_in))
    colorbar_axes = fig.add_axes((0.88, 0.75 / height_in + 0.1, 0.025, 1 - 1.45 / height_in - 0.2))
    cov = None if draw_floor(ax, trace) else views.coverage(trace)  # (a drawn floor: the picture, not the cover)
    if cov is not None:
        image = np.zeros(cov.free.shape, dtype=int)
        image[cov.free] = 1
        image[cov.covered] = 2
        cmap = ListedColormap([(1, 1, 1, 0), FREE_RGBA, COVERED_RGBA])
        ax.imshow(image, origin="lower", extent=cov.extent, cmap=cmap, vmin=0, vmax=2, interpolation="nearest")
    if world:
        for ax_, ay_, bx_, by_ in world["segments"]:
            ax.plot([ax_, bx_], [ay_, by_], color="#263238", linewidth=3, solid_capstyle="round")
    x, y, t_s = tr["x_m"], tr["y_m"], tr["t_us"] / 1e6
    points = np.column_stack([x, y]).reshape(-1, 1, 2)
    path = LineCollection(np.concatenate([points[:-1], points[1:]], axis=1), cmap="viridis", linewidth=2)
    path.set_array(t_s[:-1])
    ax.add_collection(path)
    fig.colorbar(path, cax=colorbar_axes, label="virtual time (s)")
    belief = views.belief_path(trace)
    if belief is not None:
        ax.plot(belief.x_m, belief.y_m, "--", color="#ef6c00", linewidth=1.5, label=f"{belief.what} (firmware)")
    ax.plot(x[0], y[0], "o", color=OK_COLOUR, markersize=9, label="start")
    ax.plot(x[-1], y[-1], "s", color="#1565c0", markersize=8, label="end")
    if "theta_rad" in tr:
        th = tr["theta_rad"][-1]
        ax.annotate(
            "",
            xy=(x[-1] + 0.3 * np.cos(th), y[-1] + 0.3 * np.sin(th)),
            xytext=(x[-1], y[-1]),
            arrowprops={"arrowstyle": "->", "color": "#1565c0", "lw": 2},
        )
    contacts = trace.header.get("contacts", [])
    if contacts:
        cx, cy = [c[1] for c in contacts], [c[2] for c in contacts]
        ax.plot(cx, cy, "x", color=MISS_COLOUR, markersize=10, markeredgewidth=2.5, label=f"contact ({len(contacts)})")
    if cov is not None:
        ax.plot([], [], "s", color=COVERED_RGBA, markersize=10, label=f"covered floor ({cov.fraction:.0%})")
    ax.set_aspect("equal")
    lo = np.nanmin(np.column_stack([x, y]), axis=0)
    hi = np.nanmax(np.column_stack([x, y]), axis=0)
    if world:
        seg = np.asarray(world["segments"], dtype=float)
        lo = np.minimum(lo, [seg[:, [0, 2]].min(), seg[:, [1, 3]].min()])
        hi = np.maximum(hi, [seg[:, [0, 2]].max(), seg[:, [1, 3]].max()])
    pad = 0.03 * max(hi - lo) + 0.05
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    fig.legend(loc="lower center", ncols=5, fontsize="small", frameon=False)
    covered = f", {cov.fraction:.0%} of the floor covered" if cov is not None else ""
    ax.set_title(f"Trajectory (ground truth){covered}\n{_title(trace)}", fontsize="medium")
    return fig


def draw_floor(ax, trace: TraceData) -> bool:
    """The floor's picture under the path, where the world has one drawn: True if drawn."""
    floor = views.floor_picture(trace)
    if floor is not None:
        ax.imshow(
            floor.gray, cmap="gray", vmin=0, vmax=255, extent=floor.extent, origin="upper", interpolation="nearest"
        )
    return floor is not None


# -- signals -----------------------------------------------------------------------------


def signals_figure(trace: TraceData) -> Figure | None:
    panels = views.signal_panels(trace)
    if not panels:
        return None
    height_in = 2.4 * len(panels) + 0.8
    fig = Figure(figsize=(12, height_in))  # (the legends right of the panels, over no line)
    fig.subplots_adjust(
        left=0.07, right=1 - LEGEND_WIDTH_IN / 12, bottom=0.6 / height_in, top=1 - 0.8 / height_in, hspace=0.35
    )
    axes = fig.subplots(len(panels), 1, sharex=True, squeeze=False)[:, 0]
    bumps = views.bumps_s(trace)
    end_s = trace.header["t_end_us"] / 1e6
    for ax, panel in zip(axes, panels):
        _draw_panel(ax, panel, bumps, end_s)
    axes[-1].set_xlabel("virtual time (s)" + ("; red lines: contacts with a wall" if len(bumps) else ""))
    axes[-1].set_xlim(0, trace.header["t_end_us"] / 1e6)
    fig.suptitle(f"Signals over time: {_title(trace)}", fontsize="medium")
    return fig


def _draw_colours(ax, line: views.Line, row: int, end_s: float | None) -> None:
    """A LED's colours (0xRRGGBB) as bars on row ``row``, each until the next change."""
    ends = np.append(line.t_s[1:], end_s if end_s is not None else line.t_s[-1])
    for start, end, rgb in zip(line.t_s, ends, line.values.astype(int)):
        colour = ((rgb >> 16 & 0xFF) / 255, (rgb >> 8 & 0xFF) / 255, (rgb & 0xFF) / 255)
        ax.broken_barh([(start, max(end - start, 0.0))], (row + 0.1, 0.8), facecolors=[colour], edgecolor="#9e9e9e")
    ax.text(0, row + 0.5, f" {line.label}", fontsize="x-small", va="center", color="#455a64")


def _draw_panel(ax, panel: views.Panel, bumps, end_s: float | None = None) -> None:
    """The panel's lines; a step line holds its last value to ``end_s`` (the run's end)."""
    ax.ticklabel_format(axis="y", useOffset=False)  # 90 degrees, not 1e-3 + 8.999e1
    rows = 0
    for line in panel.lines:
        if line.style == "colours":
            _draw_colours(ax, line, rows, end_s)
            rows += 1
        elif line.style == "points":
            ax.plot(line.t_s, line.values, ".", markersize=4, label=line.label)
        elif line.style in ("step", "dashed"):
            dashes = "--" if line.style == "dashed" else "-"
            t_s, values = line.t_s, line.values
            if end_s is not None and len(t_s) and t_s[-1] < end_s:
                t_s, values = np.append(t_s, end_s), np.append(values, values[-1])
            ax.step(t_s, values, dashes, where="post", linewidth=1.2, label=line.label)
        else:
            ax.plot(line.t_s, line.values, linewidth=1.2, label=line.label)
    for value, label in panel.levels:
        ax.axhline(value, color="#546e7a", linestyle=":", linewidth=1, label=label or None)
    for t in bumps:
        ax.axvline(t, color=MISS_COLOUR, linewidth=0.8, alpha=0.6)
    if panel.notes:
        ax.text(
            0.01,
            0.03,
            "\n".join(panel.notes),
            transform=ax.transAxes,
            fontsize="x-small",
            va="bottom",
            bbox={"boxstyle": "round", "facecolor": "#fffde7", "edgecolor": "#bdbdbd", "alpha": 0.95},
        )
    ax.set_title(panel.title, fontsize="medium", loc="left")
    ax.set_ylabel(panel.ylabel)
    ax.grid(True, alpha=0.3)
    handles, labels = ax.get_legend_handles_labels()
    labels = [textwrap.fill(label, LEGEND_CHARS) for label in labels]
    ax.legend(
        handles,
        labels,
        loc="upper left",
        bbox_to_anchor=(1.01, 1.0),
        fontsize="x-small",
        frameon=False,
        borderaxespad=0,
    )


# -- timing ------------------------------------------------------------------------------


def timing_figure(trace: TraceData) -> Figure | None:
    budgets = [b for b in trace.budgets if _has_values(b)]
    if not budgets:
        return None
    cols = 2 if len(budgets) > 1 else 1
    rows = (len(budgets) + cols - 1) // cols
    height_in = 2.9 * rows + 0.6
    fig = Figure(figsize=(8, height_in))  # fixed margins: constrained layout costs a second on log axes
    fig.subplots_adjust(
        left=0.1, right=0.98, bottom=0.55 / height_in, top=1 - 0.95 / height_in, hspace=0.75, wspace=0.3
    )
    axes = fig.subplots(rows, cols, squeeze=False).ravel()
    for ax, budget in zip(axes, budgets):
        try:
            _budget_histogram(ax, budget)
        except (KeyError, TypeError, ValueError, AttributeError) as e:  # a damaged budgets.json: say so, plot the rest
            ax.clear()
            ax.set_axis_off()
            ax.text(
                0.5,
                0.5,
                f"budgets.json: a record not readable\n({type(e).__name__}: {e})",
                ha="center",
                fontsize="small",
            )
    for ax in axes[len(budgets) :]:
        ax.set_visible(False)
    fig.suptitle(f"Timing budgets: {_title(trace)}", fontsize="medium")
    return fig


def cpu_figure(trace: TraceData) -> Figure | None:
    """With MCU time (docs/mcu-time.md): the firmware's CPU load, the busy share of each
    window of virtual time (the header's ``mcu_time``), and its longest compute stretches."""
    mcu = trace.header.get("mcu_time")
    if not isinstance(mcu, dict) or not mcu.get("busy_share"):
        return None
    shares = np.array(mcu["busy_share"], dtype=float) * 100
    window_s = mcu["window_us"] / 1e6
    t = np.arange(len(shares)) * window_s
    fig = Figure(figsize=(8, 2.8))
    fig.subplots_adjust(left=0.1, right=0.98, bottom=0.18, top=0.82)
    ax = fig.subplots()
    irq = np.array(mcu.get("callbacks_share") or [0.0] * len(shares), dtype=float) * 100
    ax.fill_between(t, shares, step="post", color="#1565c0", alpha=0.3, label="main program")
    ax.fill_between(t, shares, shares + irq, step="post", color="#ef6c00", alpha=0.35, label="callbacks (IRQs, Timers)")
    ax.step(t, shares + irq, where="post", color="#263238", linewidth=1)
    ax.axhline(100, color="#263238", linewidth=0.8, linestyle="--")
    for i, s in enumerate(mcu.get("longest") or ()):
        label = "the longest compute stretches" if i == 0 else None
        ax.axvline(s["t_us"] / 1e6, color=MISS_COLOUR, linewidth=0.8, alpha=0.6, label=label)
    ax.legend(loc="upper right", fontsize="x-small", framealpha=0.8)
    ax.set_ylim(0, max(105, float((shares + irq).max()) * 1.05))
    ax.set_xlim(0, max(t[-1] + window_s, window_s))
    ax.set_xlabel("virtual time (s)")
    ax.set_ylabel(f"busy % of {mcu['window_us'] // 1000} ms")
    total = shares + irq
    over = " (over 100 %: the board would fall behind)" if total.max() > 100 else ""
    fig.suptitle(
        f"CPU load on {mcu['cpu']}: mean {total.mean():.1f} %, peak {total.max():.0f} %{over}\n" + _title(trace),
        fontsize="small",
    )
    return fig


def _has_values(budget) -> bool:
    try:
        return bool(len(budget_values(budget)[0]))
    except (KeyError, TypeError, ValueError, AttributeError):
        return isinstance(budget, dict)  # (drawn as a record not readable)


def budget_values(budget: dict) -> tuple[np.ndarray, np.ndarray]:
    """A budget record's distinct values (us) and how many times each was measured:
    ``histogram_us`` pairs, or (a trace folder written before budgets kept histograms)
    ``values_us``, every value once."""
    if "histogram_us" in budget:
        pairs = np.asarray(budget["histogram_us"], dtype=float).reshape(-1, 2)
        return pairs[:, 0], pairs[:, 1]
    values = np.asarray(budget.get("values_us", []), dtype=float)
    return values, np.ones_like(values)


def _budget_histogram(ax, budget: dict) -> None:
    values_us, counts = budget_values(budget)
    values_ms = values_us / 1000
    stats = budget["stats"]
    unit = "ms of wall time" if budget.get("wall_clock") else "ms"
    period = budget.get("period_us")
    if period is not None and "tolerance_us" in budget:
        lo, hi = (period - budget["tolerance_us"]) / 1000, (period + budget["tolerance_us"]) / 1000
        ax.axvspan(
            lo,
            hi,
            color=OK_COLOUR,
            alpha=0.15,
            label=f"allowed {period / 1000:g} ± {budget['tolerance_us'] / 1000:g} ms",
        )
        ax.axvline(lo, color=MISS_COLOUR, linewidth=1)
        ax.axvline(hi, color=MISS_COLOUR, linewidth=1)
        span = (min(lo, values_ms.min()), max(hi, values_ms.max()))
    else:
        limit = budget["limit_us"] / 1000
        ax.axvline(limit, color=MISS_COLOUR, linewidth=1.5, label=f"limit {limit:g} {unit}")
        span = (min(0.0, values_ms.min()), max(limit, values_ms.max()))
    positive = values_ms[values_ms > 0]
    if len(positive) == len(values_ms) and span[1] / positive.min() > 100:  # several decades: log axis
        bins = np.geomspace(positive.min() * 0.9, span[1] * 1.1, 41)
        ax.set_xscale("log")
        _plain_log_labels(ax.xaxis)
    else:
        width = max(span[1] - span[0], 1e-3)
        bins = np.linspace(span[0] - 0.05 * width, span[1] + 0.05 * width, 41)
    verdict, colour = budget_verdict(budget)
    ax.hist(values_ms, bins=bins, weights=counts, color=colour, alpha=0.85, histtype="stepfilled")
    ax.set_yscale("log")  # a single late value stays visible beside hundreds on time
    ax.set_ylim(0.7, None)  # bars rise from below a count of 1
    _plain_log_labels(ax.yaxis)
    ax.set_xlabel(unit)
    ax.set_ylabel("count")
    ax.set_title(
        f"{budget['name']}: {verdict}, {_misses_text(budget)} of {stats['count']}\n"
        f"p50 {stats['p50'] / 1000:g} ms, p99 {stats['p99'] / 1000:g} ms, max {stats['max'] / 1000:g} ms",
        fontsize="small",
        color=colour,
    )


VERDICT_COLOURS = {
    verdicts.HELD: OK_COLOUR,
    verdicts.TOLERATED: TOLERATED_COLOUR,
    verdicts.MISSED: MISS_COLOUR,
    verdicts.INFO: INFO_COLOUR,
}


def budget_verdict(budget: dict) -> tuple[str, str]:
    """(verdict, colour) of a budget record: the verdict its test gave it (``budgets.json``
    as the pytest plugin stamps it), else, for a run no test judged (``mpy-fil run``),
    ``held`` or ``N misses``, amber: measured, not enforced."""
    verdict = budget.get("verdict")
    if verdict is None:
        if budget.get("wall_clock"):
            return verdicts.INFO, INFO_COLOUR
        misses = budget["stats"]["misses"]
        return (
            (f"{misses} {'miss' if misses == 1 else 'misses'} (no test judged them)", TOLERATED_COLOUR)
            if misses
            else (
                verdicts.HELD,
                OK_COLOUR,
            )
        )
    return verdict, VERDICT_COLOURS.get(verdict, INFO_COLOUR)


def _misses_text(budget: dict) -> str:
    misses, replaced = budget["stats"]["misses"], budget.get("replaced") or 0
    text = f"{misses} {'miss' if misses == 1 else 'misses'}"
    if replaced:
        text += f" ({'all' if replaced == misses else replaced} replaced before read)"
    return text


def _plain_log_labels(axis) -> None:
    """1, 10, 100 rather than mathtext powers of ten, and no minor ticks: clearer, and
    cheaper to draw."""
    axis.set_major_formatter(FuncFormatter(lambda v, _pos: f"{v:g}"))
    axis.set_minor_locator(NullLocator())
