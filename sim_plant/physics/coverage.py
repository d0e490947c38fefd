"""The floor's coverage grid: which cells a robot's cleaning footprint has swept.

Ground truth only (no sensor sees it). The plant records the path as pose samples
(cheap, one tuple every ``sample_period_us``); the grid rasterises them lazily, a
batch of path segments at a time, marking every cell whose centre lies within the
footprint's half-width of the path (a capsule around each segment).
"""

import math

import numpy as np

from sim_plant.engine import Part
from sim_plant.plant import NEVER_US
from sim_plant.world import World

SAMPLE_STEP_CELLS = 0.5
"""While the robot moves, the path is sampled every half cell of travel ..."""
SAMPLE_PERIOD_MIN_US = 20_000
SAMPLE_PERIOD_MAX_US = 500_000
"""... but no more often than every 20 ms, and at least every 500 ms (turns on the spot)."""
BEND_RAD = math.radians(3.0)
"""A change of motion adds a sample where the path has turned this much since the last
one (a chord over a turn this small is off the path by under 1/100 of its length)."""
FLUSH_POINTS = 32
"""Rasterise once this many path samples are waiting (keeps plant snapshots small)."""
FEW_SEGMENTS = 3
"""Up to this many segments at once are swept one by one (fewer, smaller arrays)."""


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
        self.free.flags.writeable = False  # fixed: snapshots share it
        self.covered = np.zeros((self.ny, self.nx), dtype=bool)
        self.free_cells = int(self.free.sum())
        # each column's and row's centre, as Python floats (tuples: fixed, and no copy in a snapshot)
        self.centres_x = tuple(x0 + (i + 0.5) * cell_m for i in range(self.nx))
        self.centres_y = tuple(y0 + (j + 0.5) * cell_m for j in range(self.ny))
        self.covered_free = 0  # free cells swept so far: kept up by _sweep, fraction() reads it
        self.pending: list[tuple[float, float]] = []

    def add_point(self, x_m: float, y_m: float) -> None:
        self.pending.append((x_m, y_m))
        if len(self.pending) >= FLUSH_POINTS:
            self.flush()

    def flush(self) -> None:
        """Rasterise the waiting path samples (all segments at once)."""
        pts = self.pending
        if len(pts) == 1:
            self._sweep(np.array(pts[:1], dtype=float), np.array(pts[:1], dtype=float))
        elif len(pts) >= 2:
            arr = np.array(pts, dtype=float)
            self._sweep(arr[:-1], arr[1:])
        self.pending = pts[-1:]

    def sweep_to(self, x_m: float, y_m: float) -> None:
        """flush(), then the segment from the last sample to (x_m, y_m), in one pass (the
        same cells: each sample lies on a segment swept here); the samples stay as
        flush() leaves them. Ground truth asks for this every 50 ms."""
        pts = self.pending
        if not pts:
            return
        if len(pts) <= FEW_SEGMENTS:
            path = [*pts, (x_m, y_m)]
            self._sweep_few(path[:-1], path[1:])
        else:
            arr = np.array([*pts, (x_m, y_m)], dtype=float)
            self._sweep(arr[:-1], arr[1:])
        self.pending = pts[-1:]

    def sweep(self, ax: float, ay: float, bx: float, by: float) -> None:
        """Mark the footprint along one segment."""
        self._sweep(np.array([[ax, ay]]), np.array([[bx, by]]))

    def _sweep(self, a, b) -> None:
        """Mark every cell whose centre is within the half-width of any segment a[k]-b[k]."""
        if len(a) <= FEW_SEGMENTS:
            self._sweep_few(a.tolist(), b.tolist())
            return
        r, c = self.half_width_m, self.cell_m
        lo = np.minimum(a.min(axis=0), b.min(axis=0)) - r
        hi = np.maximum(a.max(axis=0), b.max(axis=0)) + r
        box = self._box(lo[0], lo[1], hi[0], hi[1])
        if box is None:
            return
        i0, i1, j0, j1 = box
        cx = self.x0_m + (np.arange(i0, i1) + 0.5) * c
        cy = self.y0_m + (np.arange(j0, j1) + 0.5) * c
        px = np.repeat(cx[None, :], j1 - j0, axis=0).ravel()[:, None] - a[None, :, 0]
        py = np.repeat(cy[:, None], i1 - i0, axis=1).ravel()[:, None] - a[None, :, 1]
        u = b - a
        l2 = (u * u).sum(axis=1)
        s = np.clip((px * u[:, 0] + py * u[:, 1]) / np.where(l2 > 0, l2, 1.0), 0.0, 1.0)
        dx, dy = px - s * u[:, 0], py - s * u[:, 1]
        hit = ((dx * dx + dy * dy) <= r * r).any(axis=1)
        self._mark(j0, i0, hit.reshape(j1 - j0, i1 - i0))

    def _box(self, lo_x: float, lo_y: float, hi_x: float, hi_y: float) -> tuple[int, int, int, int] | None:
        """The cells (columns i0:i1, rows j0:j1) of the box [lo, hi], or None if it misses the grid."""
        x0, y0, c = self.x0_m, self.y0_m, self.cell_m
        i0, i1 = max(0, int((lo_x - x0) / c)), min(self.nx, int((hi_x - x0) / c) + 1)
        j0, j1 = max(0, int((lo_y - y0) / c)), min(self.ny, int((hi_y - y0) / c) + 1)
        return None if i0 >= i1 or j0 >= j1 else (i0, i1, j0, j1)

    def _sweep_few(self, a, b) -> None:
        """_sweep for a few segments (ground truth sweeps one or two every 50 ms): the box's
        cells not yet swept found in its bytes, then each of them tested in Python, the same
        arithmetic as the arrays' element by element (most of a moving robot's box is swept
        already; of the rest, most are the box's corners, which the footprint never reaches)."""
        r = self.half_width_m
        if len(a) == 1:  # (one segment: the usual)
            (ax, ay), (bx, by) = a[0], b[0]
            if ax != ax or ay != ay or bx != bx or by != by:  # (as the arrays' int() of a NaN bound raises)
                raise ValueError("coverage grid: a path point is NaN")
            lo_x, hi_x = (ax, bx) if ax <= bx else (bx, ax)
            lo_y, hi_y = (ay, by) if ay <= by else (by, ay)
            box = self._box(lo_x - r, lo_y - r, hi_x + r, hi_y + r)
            ux, uy = bx - ax, by - ay
            l2 = ux * ux + uy * uy
            segs = [(ax, ay, ux, uy, l2 if l2 > 0 else 1.0)]
            # (a cell farther from the segment's middle than r and half its length is missed
            # for sure: the box's corners, passed over at a third of the test's arithmetic; the
            # bound is widened by far more than any rounding, so no cell near the edge goes)
            mx, my = (ax + bx) / 2, (ay + by) / 2
            reach = (r + math.sqrt(l2) / 2) * (1 + 1e-9)
            reach2 = reach * reach
        else:
            mx = my = 0.0
            reach2 = math.inf
            xs_, ys_ = [p[0] for p in a] + [p[0] for p in b], [p[1] for p in a] + [p[1] for p in b]
            if any(v != v for v in xs_ + ys_):
                raise ValueError("coverage grid: a path point is NaN")
            box = self._box(min(xs_) - r, min(ys_) - r, max(xs_) + r, max(ys_) + r)
            segs = []
            for (ax, ay), (bx, by) in zip(a, b):
                ux, uy = bx - ax, by - ay
                l2 = ux * ux + uy * uy
                segs.append((ax, ay, ux, uy, l2 if l2 > 0 else 1.0))
        if box is None:
            return
        i0, i1, j0, j1 = box
        covered = self.covered
        swept = covered[j0:j1, i0:i1].tobytes()  # (a byte a cell, row by row: 0 not yet swept)
        k = swept.find(0)
        if k < 0:
            return
        r2, w = r * r, i1 - i0
        cxs, cys, free = self.centres_x, self.centres_y, self.free
        new = 0
        while k >= 0:
            j, i = divmod(k, w)
            j += j0
            i += i0
            cx, cy = cxs[i], cys[j]
            if (cx - mx) * (cx - mx) + (cy - my) * (cy - my) > reach2:
                k = swept.find(0, k + 1)
                continue
            for ax, ay, ux, uy, l2 in segs:
                px, py = cx - ax, cy - ay
                s = (px * ux + py * uy) / l2
                s = 0.0 if s < 0.0 else 1.0 if s > 1.0 else s
                dx, dy = px - s * ux, py - s * uy
                if dx * dx + dy * dy <= r2:
                    covered[j, i] = True
                    new += bool(free[j, i])
                    break
            k = swept.find(0, k + 1)
        self.covered_free += new

    def _mark(self, j0: int, i0: int, hit) -> None:
        j1, i1 = j0 + hit.shape[0], i0 + hit.shape[1]
        region = self.covered[j0:j1, i0:i1]
        self.covered_free += int(np.count_nonzero(hit & ~region & self.free[j0:j1, i0:i1]))
        region |= hit

    def fraction(self, flush: bool = True) -> float:
        """Share of the free floor swept so far (``flush``: the waiting samples first)."""
        if flush:
            self.flush()
        free = self.free_cells
        return float(self.covered_free) / free if free else 0.0  # (as (covered & free).sum(), kept up)

    def fraction_in(self, x0_m: float, x1_m: float, y0_m: float, y1_m: float) -> float:
        """Share swept of the free cells whose centre lies in the box [x0, x1] x [y0, y1]."""
        self.flush()
        xs = self.x0_m + (np.arange(self.nx) + 0.5) * self.cell_m
        ys = self.y0_m + (np.arange(self.ny) + 0.5) * self.cell_m
        box = ((xs >= x0_m) & (xs <= x1_m))[None, :] & ((ys >= y0_m) & (ys <= y1_m))[:, None] & self.free
        n = int(box.sum())
        if not n:
            raise ValueError(f"no free cell in x {x0_m}..{x1_m} m, y {y0_m}..{y1_m} m")
        return float((self.covered & box).sum()) / n


def _free_mask(world: World, xs, ys):
    """Even-odd crossing test of every cell centre against every wall, vectorised."""
    gx, gy = np.meshgrid(xs, ys)
    inside = np.zeros(gx.shape, dtype=bool)
    for ax, ay, _ux, _uy, _length, bx, by, *_ in world.walls:
        if ay == by:
            continue
        straddles = (ay > gy) != (by > gy)
        x_cross = ax + (gy - ay) * (bx - ax) / (by - ay)
        inside ^= straddles & (x_cross > gx)
    return inside


class CoverageRecorder(Part):
    """Samples the path into a :class:`CoverageGrid`: every half cell of travel while the
    robot moves, where it stops or turns back, and at a change of motion once the path
    has bent ``BEND_RAD`` since the last sample (a board trims its wheel speeds every
    control step: those changes leave the path straight)."""

    def __init__(self, grid: CoverageGrid):
        self.grid = grid
        self.period_us = SAMPLE_PERIOD_MAX_US
        self.next_us = NEVER_US
        self.last_th = 0.0  # heading at the last sample
        self.direction = 0  # sign of the forward speed since the last change of motion

    def _sample(self, t_us: int, plant) -> None:
        x, y, self.last_th = plant.pose_at(t_us)
        self.grid.add_point(x, y)

    def start(self, t_us: int, plant) -> None:
        self._sample(t_us, plant)

    def jump(self, t_us: int, plant) -> None:
        """The robot was carried to where it is now: its path starts again here (nothing
        is swept between the two places)."""
        self.grid.flush()
        self.grid.pending = []
        self._sample(t_us, plant)

    def on_motion_change(self, t_us: int, plant) -> None:
        body = plant.drive.body
        speed = abs(body.v)
        direction = (body.v > 0.0) - (body.v < 0.0)
        turned_back, self.direction = direction != self.direction, direction
        if speed == 0.0 and body.w == 0.0 and body.segment is None:
            self._sample(t_us, plant)
            self.next_us = NEVER_US
            return
        moving = self.next_us != NEVER_US
        if (
            not moving
            or turned_back
            or abs(math.remainder(plant.pose_at(t_us)[2] - self.last_th, 2 * math.pi)) > BEND_RAD
        ):
            self._sample(t_us, plant)
            moving = False  # plan from this sample
        period = SAMPLE_STEP_CELLS * self.grid.cell_m / speed * 1e6 if speed > 0.0 else SAMPLE_PERIOD_MAX_US
        self.period_us = int(min(max(period, SAMPLE_PERIOD_MIN_US), SAMPLE_PERIOD_MAX_US))
        self.next_us = min(self.next_us, t_us + self.period_us) if moving else t_us + self.period_us

    def fire(self, t_us: int, plant, out: list) -> None:
        self._sample(t_us, plant)
        self.next_us = t_us + self.period_us

    def truth(self, t_us: int, plant) -> dict:
        x, y, _ = plant.pose_at(t_us)
        self.grid.sweep_to(x, y)  # up to now (marks cells the robot has swept; keeps the samples)
        return {"coverage_fraction": self.grid.fraction(flush=False)}
