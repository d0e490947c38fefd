"""Where a campaign's worst runs missed the floor: for each run that left its coverage
grid (``runs/<key>/coverage.npz``, written by the worker), a map of the floor with the
cells it covered and the cells it missed (``maps/<key>.png`` beside the page), and the
missed area by where it lies: along which wall, or in the middle between lanes
(``docs/campaigns.md``)."""

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from host.core import safefs

WALL_BAND_M = 0.5
"""A missed cell this near a wall is counted as that wall's."""
COVERED_RGB = (0.55, 0.80, 0.55)
MISSED_RGB = (0.84, 0.16, 0.16)
OUTSIDE_RGB = (1.0, 1.0, 1.0)


@dataclass
class FloorMap:
    key: str
    image: Path  # the PNG, beside the page
    covered: float  # fraction of the free floor
    missed_m2: float
    where: list[tuple[str, float]]  # (place, square metres missed there), most first

    def caption(self) -> str:
        places = ", ".join(f"{area:.2f} m² {place}" for place, area in self.where if area >= 0.005)
        return f"{self.covered:.1%} covered; {self.missed_m2:.2f} m² missed" + (f": {places}" if places else "")


def missed_by_place(covered: np.ndarray, free: np.ndarray, extent, band_m: float = WALL_BAND_M) -> dict[str, float]:
    """The missed free floor, in square metres, by place: within ``band_m`` of one edge of
    the floor, at the lowest or highest x (an end wall) or y (a side wall); within it of
    two (a corner); or the middle."""
    ny, nx = free.shape
    cell_m = (extent[1] - extent[0]) / nx
    rows, cols = np.nonzero(free)
    if not len(rows):
        return {}
    i0, i1, j0, j1 = cols.min(), cols.max(), rows.min(), rows.max()
    x = lambda i: extent[0] + (i + 0.5) * cell_m  # noqa: E731 (cell centres in metres)
    y = lambda j: extent[2] + (j + 0.5) * cell_m  # noqa: E731
    missed_j, missed_i = np.nonzero(free & ~covered)
    places = {
        f"along the end wall at x = {x(i0) - cell_m / 2:.1f} m": (missed_i - i0) * cell_m,
        f"along the end wall at x = {x(i1) + cell_m / 2:.1f} m": (i1 - missed_i) * cell_m,
        f"along the side wall at y = {y(j0) - cell_m / 2:.1f} m": (missed_j - j0) * cell_m,
        f"along the side wall at y = {y(j1) + cell_m / 2:.1f} m": (j1 - missed_j) * cell_m,
    }
    names = list(places)
    distance = np.vstack([places[n] for n in names]) if len(missed_i) else np.zeros((4, 0))
    walls = (distance < band_m).sum(axis=0)
    nearest = distance.argmin(axis=0)
    area = cell_m * cell_m
    out = {n: float(((nearest == k) & (walls == 1)).sum() * area) for k, n in enumerate(names)}
    out["in the corners"] = float((walls >= 2).sum() * area)
    out["in the middle, between lanes"] = float((walls == 0).sum() * area)
    return out


def draw_map(grid: dict, path: Path, title: str) -> None:
    """The floor: covered cells green, missed red, the start and end marked."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    covered, free, extent = grid["covered"], grid["free"], grid["extent"]
    image = np.ones(free.shape + (3,)) * np.array(OUTSIDE_RGB)
    image[free] = MISSED_RGB
    image[covered & free] = COVERED_RGB
    width_m, height_m = extent[1] - extent[0], extent[3] - extent[2]
    fig, ax = plt.subplots(figsize=(7, max(2.6, min(7.0, 7 * height_m / max(width_m, 1e-9) + 1.2))))
    ax.imshow(image, origin="lower", extent=tuple(extent), interpolation="nearest")
    marks = (("start", grid.get("start"), "o", "#2e7d32"), ("end", grid.get("end"), "s", "#1565c0"))
    for name, pose, marker, colour in marks:
        if pose is not None and all(math.isfinite(v) for v in pose[:2]):
            ax.plot(pose[0], pose[1], marker, color=colour, markersize=8, markeredgecolor="#fff", label=name)
    ax.plot([], [], "s", color=COVERED_RGB, markersize=9, label="covered")
    ax.plot([], [], "s", color=MISSED_RGB, markersize=9, label="missed")
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(title, fontsize="medium")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.18), ncols=4, fontsize="small", frameon=False)
    fig.tight_layout()
    with safefs.replacing(path) as temp:
        fig.savefig(temp, dpi=90, format="png")
    plt.close(fig)


def coverage_maps(out: Path, runs: list[dict]) -> dict[str, FloorMap]:
    """A map per run of ``runs`` that left its coverage grid in ``out/runs/<key>/``; key -> map."""
    maps = {}
    for r in runs:
        source = Path(out) / "runs" / r["key"] / "coverage.npz"
        if not source.is_file():
            continue
        with np.load(source) as data:
            grid = {k: data[k] for k in data.files}
        folder = safefs.make_folder(Path(out) / "maps")  # (maps/ a link: refused)
        image = folder / (r["key"].replace("/", "_") + ".png")
        free, covered = grid["free"], grid["covered"]
        cell_m2 = ((grid["extent"][1] - grid["extent"][0]) / free.shape[1]) ** 2
        where = missed_by_place(covered, free, grid["extent"])
        fmap = FloorMap(
            key=r["key"],
            image=image,
            covered=float((covered & free).sum() / max(1, free.sum())),
            missed_m2=float((free & ~covered).sum() * cell_m2),
            where=sorted(where.items(), key=lambda kv: -kv[1]),
        )
        draw_map(grid, image, f"{r['key']}: {fmap.covered:.1%} of the floor covered")
        maps[r["key"]] = fmap
    return maps
