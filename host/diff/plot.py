"""Both runs of a diff on one figure (PNG, matplotlib's Agg canvas): the two paths over
the floor, the distance between the poses over time, and each firmware output that
diverged, as a step line of each run around its first divergence."""

from pathlib import Path

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from host.artefacts import integrity
from host.core import safefs
from host.diff.compare import Diff

DPI = 100
OUTPUTS_SHOWN = 4
AROUND_S = 2.0  # an output's panel: this long either side of its first divergence
NAME = "diff.png"
TEXT_LEVELS_SHOWN = 8  # a text output's panel: this many of its values named on the axis
TEXT_CHARS = 28


def _runs(diff: Diff):
    return ((diff.a, "A", "-"), (diff.b, "B", "--"))


def _changes(trace, name: str) -> list[tuple[int, object]]:
    """(t_us, value) of each change of one output, its values as recorded (numbers or text)."""
    return [(t, v) for t, n, v in trace.events if n == name]


def _short(text: str) -> str:
    return text if len(text) <= TEXT_CHARS else text[: TEXT_CHARS - 3] + "..."


def plot_diff(diff: Diff, out: Path) -> Path:
    """Write ``out/diff.png``; its path."""
    diverged = sorted((o for o in diff.outputs if o["first_t_s"] is not None), key=lambda o: o["first_t_s"])
    diverged = diverged[:OUTPUTS_SHOWN]
    fig = Figure(figsize=(11, 4 + 2 * len(diverged)))
    grid = fig.add_gridspec(1 + len(diverged), 2, height_ratios=[2] + [1] * len(diverged))
    _paths(fig.add_subplot(grid[0, 0]), diff)
    _deviation(fig.add_subplot(grid[0, 1]), diff)
    for row, output in enumerate(diverged, start=1):
        _output(fig.add_subplot(grid[row, :]), diff, output)
    fig.suptitle(f"A: {diff.a.folder}\nB: {diff.b.folder}", fontsize=9)
    fig.tight_layout()
    path = safefs.make_folder(out) / NAME  # (a link at out: refused)
    FigureCanvasAgg(fig)
    with integrity.atomic(path) as part:
        fig.savefig(part, dpi=DPI, format="png")
    return path


def _paths(ax, diff: Diff) -> None:
    for trace, label, style in ((diff.a, "A", "-"), (diff.b, "B", "--")):
        if "x_m" in trace.truth and "y_m" in trace.truth:
            ax.plot(trace.truth["x_m"], trace.truth["y_m"], style, label=label)
    ax.set_title("path (ground truth)")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_aspect("equal", adjustable="datalim")
    if ax.lines:
        ax.legend()
    else:
        ax.text(0.5, 0.5, "no pose in both", ha="center", transform=ax.transAxes)


def _deviation(ax, diff: Diff) -> None:
    if len(diff.position_m):
        ax.plot(diff.t_s, diff.position_m * 1000)
    else:
        ax.text(0.5, 0.5, "no pose in both", ha="center", transform=ax.transAxes)
    ax.set_title(f"distance between A's and B's pose (max {diff.max_pos_m * 1000:.1f} mm)")
    ax.set_xlabel("virtual time (s)")
    ax.set_ylabel("mm")


def _output(ax, diff: Diff, output: dict) -> None:
    t0 = output["first_t_s"]
    runs = [(label, style, _changes(trace, output["signal"])) for trace, label, style in _runs(diff)]
    values = [v for _l, _s, changes in runs for _t, v in changes]
    numeric = all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values)
    levels = {} if numeric else {v: i for i, v in enumerate(dict.fromkeys(map(str, values)))}
    for label, style, changes in runs:
        if changes:
            t_s = [t / 1e6 for t, _v in changes]
            ys = [v if numeric else levels[str(v)] for _t, v in changes]
            ax.step(t_s, ys, style, where="post", label=label)
    if levels:  # (text: a bus's transfers, a display's text, an LED's colour: each value a level)
        shown = list(levels.items())[:: max(1, len(levels) // TEXT_LEVELS_SHOWN)]
        ax.set_yticks([i for _v, i in shown], [_short(v) for v, _i in shown], fontsize=7)
    ax.axvline(t0, color="red", linewidth=0.8)
    end_s = max(trace.header.get("t_end_us", 0) for trace in (diff.a, diff.b)) / 1e6
    ax.set_xlim(max(0.0, t0 - AROUND_S), min(t0 + AROUND_S, end_s) if end_s > t0 else t0 + AROUND_S)
    ax.set_title(f"{output['signal']}: first differs at t={t0:.6f} s", fontsize=9)
    ax.legend(loc="upper right")
