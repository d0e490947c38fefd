"""The run as a moving picture: the robot's true path drawn as it happened, over the
world's walls (and the floor's picture, a line course's), written as an animated GIF
through Pillow as matplotlib's PillowWriter writes one (``plots/trajectory.gif`` beside
the still plots)."""

from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from PIL import Image

from host.artefacts import integrity
from host.artefacts.folder import TraceData
from host.report import views

FRAMES = 30  # at most: a mission of any length fits in a few seconds of GIF
FPS = 8
DPI = 60
MISSION_S = 20.0  # shorter runs get no moving picture (the still one tells them)


def write_movie(trace: TraceData, path: Path, frames: int = FRAMES) -> Path | None:
    """The GIF of ``trace``'s trajectory (None when the trace has no pose)."""
    tr = trace.truth
    if "x_m" not in tr or len(tr["x_m"]) < 2:
        return None
    if trace.header.get("t_end_us", 0) < MISSION_S * 1e6 and frames == FRAMES:
        return None
    x, y, t_s = np.asarray(tr["x_m"]), np.asarray(tr["y_m"]), np.asarray(tr["t_us"]) / 1e6
    theta = np.asarray(tr["theta_rad"]) if "theta_rad" in tr else None
    fig = Figure(figsize=(6, 4.5), dpi=DPI)
    fig.subplots_adjust(left=0.12, right=0.97, bottom=0.12, top=0.92)
    ax = fig.add_subplot()
    world = trace.header.get("world")
    points = [np.column_stack([x, y])]
    floor = views.floor_picture(trace)
    if floor is not None:  # (a line course's picture under the path)
        ax.imshow(
            floor.gray, cmap="gray", vmin=0, vmax=255, extent=floor.extent, origin="upper", interpolation="nearest"
        )
    if world:
        seg = np.asarray(world["segments"], dtype=float)
        for ax_, ay_, bx_, by_ in seg:
            ax.plot([ax_, bx_], [ay_, by_], color="#263238", linewidth=2.5)
        points.append(seg[:, :2])
        points.append(seg[:, 2:])
    every = np.concatenate(points)
    lo, hi = every.min(axis=0), every.max(axis=0)
    pad = 0.05 * max(hi - lo) + 0.05
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    (trail,) = ax.plot([], [], color="#1565c0", linewidth=1.5, animated=True)
    (body,) = ax.plot([], [], "o", color="#2e7d32", markersize=9, animated=True)
    (nose,) = ax.plot([], [], color="#2e7d32", linewidth=2, animated=True)
    title = ax.set_title("", animated=True)
    stops = np.linspace(0, len(x) - 1, min(frames, len(x))).astype(int)
    reach = 0.04 * max(hi - lo)

    def draw(k):
        trail.set_data(x[: k + 1], y[: k + 1])
        body.set_data([x[k]], [y[k]])
        if theta is not None:
            nose.set_data([x[k], x[k] + reach * np.cos(theta[k])], [y[k], y[k] + reach * np.sin(theta[k])])
        title.set_text(f"{trace.header['app']}, seed {trace.header['seed']}: t = {t_s[k]:.1f} s")
        return trail, body, nose, title

    _save_gif(fig, draw, stops, Path(path))
    return Path(path)


def _save_gif(fig: Figure, draw, stops, path: Path) -> None:
    """What matplotlib's PillowWriter writes, with the still parts (axes, ticks, walls)
    drawn once and only the moving artists drawn on them per frame (blitting, as
    FuncAnimation does on screen): a frame costs a few artists, not a whole figure."""
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    background = canvas.copy_from_bbox(fig.bbox)
    images = []
    for k in stops:
        canvas.restore_region(background)
        for artist in draw(k):
            fig.draw_artist(artist)
        size = canvas.get_width_height()
        images.append(Image.frombuffer("RGBA", size, bytes(canvas.buffer_rgba()), "raw", "RGBA", 0, 1).convert("RGB"))
    # one palette, from the last frame (it has every colour), and no dithering: Pillow's
    # own choice, a median cut per frame, costs more than drawing the frames
    palette = images[-1].quantize(colors=64, method=Image.Quantize.FASTOCTREE)
    frames = [image.quantize(palette=palette, dither=Image.Dither.NONE) for image in images]
    with integrity.atomic(path) as part:  # (a full disk leaves no GIF cut short)
        frames[0].save(part, format="GIF", save_all=True, append_images=frames[1:], duration=int(1000 / FPS), loop=0)
