"""The floor's coverage grid: which cells a robot's cleaning footprint has swept.

Ground truth only (no sensor sees it). The plant records the path as pose samples
(cheap, one tuple every ``sample_period_us``); the grid rasterises them lazily, a
batch of path segments at a time, marking every cell whose centre lies within the
footprint's half-width of the path (a capsule around each segment).
"""

import math

import numpy as np

from sim_plant.world import World

SAMPLE_PERIOD_US = 100_000
"""Path sample period while the robot moves (3 cm at 0.3 m/s: well below a cell)."""
FLUSH_POINTS = 32
"""Rasterise once this many path samples are waiting (keeps plant snapshots small)."""


class CoverageGrid:
    """Cells of ``cell_m`` over the world's bounding box; ``free`` marks cells whose
    centre is in free space, ``covered`` the ones swept so far."""

    def __init__(self, world: World, cell_m: float, half_width_m: float):
        if cell_m <= 0 or half_width_m <= 0:
            raise ValueError(f"coverage grid: cell_m ({cell_m}) and half_width_m ({half_width_m}) must be > 0")
        x0, y0, x1, y1 = world.bounds
        self.x0_m, self.y0_m, self.cell_m = x0, y0, float(cell_m)
        self.half_width_m = float(half_width_m)
        self.nx = max(1, math.ceil((x1 - x0) / cell_m - 1e-9))
        self.ny = max(1, math.ceil((y1 - y0) / cell_m - 1e-9))
        xs = x0 + (np.arange(self.nx) + 0.5) * cell_m
        ys = y0 + (np.arange(self.ny) + 0.5) * cell_m
        self.free = _free_mask(world, xs, ys)
        self.covered = np.zeros((self.ny, self.nx), dtype=bool)
        self.pending: list[tuple[float, float]] = []

    def add_point(self, x_m: float, y_m: float) -> None:
        self.pending.append((x_m, y_m))
        if len(self.pending) >= FLUSH_POINTS:
            self.flush()

    def flush(self) -> None:
        pts = self.pending
        if len(pts) >= 2:
            for (ax, ay), (bx, by) in zip(pts, pts[1:]):
                self._sweep(ax, ay, bx, by)
        elif len(pts) == 1:
            self._sweep(*pts[0], *pts[0])
        self.pending = pts[-1:]

    def _sweep(self, ax: float, ay: float, bx: float, by: float) -> None:
        r, c = self.half_width_m, self.cell_m
        i0 = max(0, int((min(ax, bx) - r - self.x0_m) / c))
        i1 = min(self.nx, int((max(ax, bx) + r - self.x0_m) / c) + 1)
        j0 = max(0, int((min(ay, by) - r - self.y0_m) / c))
        j1 = min(self.ny, int((max(ay, by) + r - self.y0_m) / c) + 1)
        if i0 >= i1 or j0 >= j1:
            return
        px = self.x0_m + (np.arange(i0, i1) + 0.5) * c - ax
        py = self.y0_m + (np.arange(j0, j1) + 0.5) * c - ay
        ux, uy = bx - ax, by - ay
        l2 = ux * ux + uy * uy
        gx, gy = np.meshgrid(px, py)
        if l2 > 0:
            s = np.clip((gx * ux + gy * uy) / l2, 0.0, 1.0)
            gx = gx - s * ux
            gy = gy - s * uy
        self.covered[j0:j1, i0:i1] |= gx * gx + gy * gy <= r * r

    def fraction(self) -> float:
        """Share of the free floor swept so far."""
        self.flush()
        free = int(self.free.sum())
        return float((self.covered & self.free).sum()) / free if free else 0.0


def _free_mask(world: World, xs, ys):
    """Even-odd crossing test of every cell centre against every wall, vectorised."""
    gx, gy = np.meshgrid(xs, ys)
    inside = np.zeros(gx.shape, dtype=bool)
    for ax, ay, _ux, _uy, _length, bx, by in world.walls:
        if ay == by:
            continue
        straddles = (ay > gy) != (by > gy)
        x_cross = ax + (gy - ay) * (bx - ax) / (by - ay)
        inside ^= straddles & (x_cross > gx)
    return inside
