"""Worlds: walls as line segments, and the geometric questions sensors and bodies ask.

A world is a set of wall segments (the boundary of the free space, plus the outline of
every obstacle). Sensors ask for the range along a ray, the nearest echo inside a cone,
or the specular returns (walls whose normal lies inside a beam); bodies ask for their
clearance to the nearest wall. Everything here is plain Python floats: a robot sees a few
walls at a time, and a loop over four to twenty segments is cheaper than a numpy call.

Factories build the seeds' worlds:

=========================  ==========================================================
factory                    world
=========================  ==========================================================
:func:`rectangle`          a rectangular room or pool, walls at 0 and w, 0 and h
:func:`pool`               the 25 x 8 m pool of seeds 000/001
:func:`room`               a rectangle with convex obstacles (seed 003's room)
:func:`duct_network`       the boundary of a union of axis-aligned duct sections
:func:`one_right_branch_duct`  seed 002's test duct: a straight duct, one right branch
:func:`multi_branch_duct`  left and right branches, one of them branching again
:func:`canyon`             seed 004's curved "canyon" as a polyline corridor
=========================  ==========================================================
"""

import math

INF = math.inf


NEAR_SLACK_M = 0.5
"""A local view of the walls is rebuilt when the robot has moved this far from where it was
built; it holds every wall within the asked reach plus this slack."""
SMALL_WORLD_WALLS = 8
"""Worlds with this few walls answer every query themselves (a view would not help)."""


def _offset_from_segment(x: float, y: float, ax: float, ay: float, ux: float, uy: float, length: float):
    """Vector from the nearest point of segment a..a+u to (x, y), and where that point
    lies on the segment (0 at a, 1 at a+u)."""
    wx, wy = x - ax, y - ay
    s = (wx * ux + wy * uy) / (length * length)
    if s <= 0.0:
        return wx, wy, 0.0
    if s >= 1.0:
        return wx - ux, wy - uy, 1.0
    return wx - s * ux, wy - s * uy, s


class World:
    """Wall segments and the queries on them.

    ``walls`` holds one tuple per segment: ``(ax, ay, ux, uy, length, bx, by, nx, ny, c)``
    with ``u = b - a``, ``n`` the unit normal (left of a->b) and ``c = n . a``.
    ``vertices`` are the segment end points (corners), deduplicated. ``floor``: what the
    floor looks like where it is drawn (a :class:`sim_plant.floor.PictureFloor`, the
    ``line_course`` world's), what line sensors see under the body's tape; None: plain.
    """

    floor = None

    def __init__(self, segments, *, name: str = "world"):
        walls = []
        for seg in segments:
            ax, ay, bx, by = (float(v) for v in seg[:4])
            ux, uy = bx - ax, by - ay
            length = math.hypot(ux, uy)
            if length > 1e-12:
                nx, ny = -uy / length, ux / length
                walls.append((ax, ay, ux, uy, length, bx, by, nx, ny, nx * ax + ny * ay))
        if not walls:
            raise ValueError(f"world {name!r} has no walls")
        self.name = name
        self.walls = tuple(walls)
        xs = [w[0] for w in walls] + [w[5] for w in walls]
        ys = [w[1] for w in walls] + [w[6] for w in walls]
        self.bounds = (min(xs), min(ys), max(xs), max(ys))
        corners = {}
        for w in walls:
            for p in ((w[0], w[1]), (w[5], w[6])):
                corners[(round(p[0], 9), round(p[1], 9))] = p
        self.vertices = tuple(corners.values())
        self._near: dict[float, tuple[float, float, World]] = {}

    def segments(self) -> list[tuple[float, float, float, float]]:
        return [(w[0], w[1], w[5], w[6]) for w in self.walls]

    def near(self, x: float, y: float, reach_m: float) -> "World":
        """A world holding at least every wall within ``reach_m`` of (x, y): queries whose
        answer lies within that reach give the same result on it, faster."""
        if len(self.walls) <= SMALL_WORLD_WALLS:
            return self
        cached = self._near.get(reach_m)
        if cached is not None and abs(x - cached[0]) <= NEAR_SLACK_M and abs(y - cached[1]) <= NEAR_SLACK_M:
            return cached[2]
        radius = reach_m + NEAR_SLACK_M * 1.5  # covers the slack box's corners
        view = World.__new__(World)
        view.name = f"{self.name} near ({x:.2f}, {y:.2f})"
        view.walls = tuple(w for w in self.walls if _point_segment_distance(x, y, w) <= radius)
        view.bounds = self.bounds
        view.vertices = tuple(v for v in self.vertices if math.hypot(v[0] - x, v[1] - y) <= radius)
        view._near = {}
        if not view.walls:  # nothing near: keep one wall so that queries stay valid
            view.walls = self.walls[:1]
        self._near[reach_m] = (x, y, view)
        return view

    # -- sensor queries ---------------------------------------------------------------

    def ray(self, x: float, y: float, angle_rad: float, max_range_m: float = INF) -> tuple[float, float]:
        """Range to the first wall along a ray, and the incidence angle there (rad from
        the wall's normal). ``(inf, nan)`` if no wall is nearer than ``max_range_m``."""
        dx, dy = math.cos(angle_rad), math.sin(angle_rad)
        best, best_cos = max_range_m, math.nan
        found = False
        for ax, ay, ux, uy, length, _bx, _by, _nx, _ny, _c in self.walls:
            den = dx * uy - dy * ux
            if -1e-12 < den < 1e-12:
                continue
            wx, wy = ax - x, ay - y
            t = (wx * uy - wy * ux) / den
            if t < 0.0 or t >= best:
                continue
            s = (wx * dy - wy * dx) / den
            if 0.0 <= s <= 1.0:
                best, best_cos, found = t, abs(den) / length, True
        if not found:
            return INF, math.nan
        return best, math.acos(min(best_cos, 1.0))

    def cone_nearest(
        self, x: float, y: float, axis_rad: float, half_angle_rad: float, max_range_m: float = INF
    ) -> float:
        """Distance to the nearest wall point inside a cone (a wedge in 2-D) of half-angle
        ``half_angle_rad`` about ``axis_rad``; ``inf`` if none within ``max_range_m``.

        The candidates on each segment are the foot of the perpendicular, the end points
        and the crossings of the two edge rays; the nearest one inside the wedge wins."""
        cx, cy = math.cos(axis_rad), math.sin(axis_rad)
        cos_half = math.cos(half_angle_rad)
        best = max_range_m
        for ax, ay, ux, uy, length, bx, by, nx, ny, c in self.walls:
            wx, wy = ax - x, ay - y
            line_d = abs(nx * x + ny * y - c)
            if line_d >= best:
                continue
            # foot of the perpendicular
            s = -(wx * ux + wy * uy) / (length * length)
            if 0.0 <= s <= 1.0:
                px, py = wx + s * ux, wy + s * uy
                if _in_wedge(px, py, line_d, cx, cy, cos_half):
                    best = line_d
                    continue
            for px, py in ((wx, wy), (bx - x, by - y)):
                d = math.hypot(px, py)
                if d < best and _in_wedge(px, py, d, cx, cy, cos_half):
                    best = d
            for edge in (-half_angle_rad, half_angle_rad):
                ex, ey = math.cos(axis_rad + edge), math.sin(axis_rad + edge)
                den = ex * uy - ey * ux
                if -1e-12 < den < 1e-12:
                    continue
                t = (wx * uy - wy * ux) / den
                if 0.0 <= t < best:
                    s = (wx * ey - wy * ex) / den
                    if 0.0 <= s <= 1.0:
                        best = t
        return best if best < max_range_m else INF

    def specular(
        self, x: float, y: float, axis_rad: float, max_incidence_rad: float, max_range_m: float
    ) -> list[tuple[float, float]]:
        """Walls that send an echo straight back: those whose normal through the sensor
        lies within ``max_incidence_rad`` of the axis and whose foot of the perpendicular
        is on the segment (seed 002, App. B.3: a wall is seen only if its normal lies in
        the cone, at its perpendicular distance). Returns ``[(distance_m, incidence_rad)]``."""
        cx, cy = math.cos(axis_rad), math.sin(axis_rad)
        cos_max = math.cos(max_incidence_rad)
        seen = []
        for ax, ay, ux, uy, length, _bx, _by, nx, ny, c in self.walls:
            sd = nx * x + ny * y - c  # signed distance; the foot lies along -sign(sd) n
            cos_inc = nx * cx + ny * cy
            if sd > 0.0:
                cos_inc = -cos_inc
            if cos_inc < cos_max:
                continue
            d = abs(sd)
            if d <= 1e-12 or d > max_range_m:
                continue
            s = ((x - ax) * ux + (y - ay) * uy) / (length * length)
            if 0.0 <= s <= 1.0:
                seen.append((d, math.acos(min(cos_inc, 1.0))))
        return seen

    def vertices_in_cone(
        self, x: float, y: float, axis_rad: float, half_angle_rad: float, max_range_m: float
    ) -> list[float]:
        """Distances to the corners (segment end points) inside a cone."""
        cx, cy = math.cos(axis_rad), math.sin(axis_rad)
        cos_half = math.cos(half_angle_rad)
        found = []
        for vx, vy in self.vertices:
            px, py = vx - x, vy - y
            d = math.hypot(px, py)
            if 1e-12 < d <= max_range_m and (px * cx + py * cy) >= cos_half * d:
                found.append(d)
        return found

    # -- bodies -----------------------------------------------------------------------

    def clearance(self, x: float, y: float) -> tuple[float, float, float]:
        """Distance from a point to the nearest wall, and the unit normal pointing from
        that wall towards the point."""
        best, bnx, bny = INF, 0.0, 0.0
        for ax, ay, ux, uy, length, _bx, _by, nx, ny, c in self.walls:
            if abs(nx * x + ny * y - c) >= best:  # the line is farther than the best so far
                continue
            px, py, _s = _offset_from_segment(x, y, ax, ay, ux, uy, length)
            d = math.hypot(px, py)
            if d < best:
                if d > 1e-12:
                    best, bnx, bny = d, px / d, py / d
                else:
                    best, bnx, bny = 0.0, nx, ny
        return best, bnx, bny

    def circle_walls(self, x: float, y: float, r: float, eps: float) -> tuple[list, float]:
        """For a circle of radius ``r`` at (x, y): the walls it touches or has gone into,
        as ``(gap, nx, ny, run)`` with gap <= ``eps`` (negative: that deep in), the normal
        pointing from the wall to the centre and ``run`` the distance from the touch point
        to the nearer end of the wall (0 when the circle touches an end point), and the
        smallest gap to any other wall."""
        touches, clear = [], INF
        limit = r + eps
        for ax, ay, ux, uy, length, _bx, _by, nx, ny, c in self.walls:
            if abs(nx * x + ny * y - c) >= clear + r:  # cannot touch, nor be nearer than the best
                continue
            px, py, s = _offset_from_segment(x, y, ax, ay, ux, uy, length)
            d = math.hypot(px, py)
            if d <= limit:
                run = min(s, 1.0 - s) * length
                if d > 1e-12:
                    touches.append((d - r, px / d, py / d, run))
                else:
                    touches.append((-r, nx, ny, run))
            elif d - r < clear:
                clear = d - r
        return touches, clear

    def contains(self, x: float, y: float) -> bool:
        """Even-odd rule: a point is in free space if a ray from it crosses the walls an
        odd number of times (inside the outer boundary, outside every obstacle)."""
        inside = False
        for ax, ay, _ux, _uy, _length, bx, by, _nx, _ny, _c in self.walls:
            if (ay > y) != (by > y):
                x_cross = ax + (y - ay) * (bx - ax) / (by - ay)
                if x_cross > x:
                    inside = not inside
        return inside


def _point_segment_distance(x: float, y: float, wall) -> float:
    ax, ay, ux, uy, length = wall[:5]
    s = min(max(((x - ax) * ux + (y - ay) * uy) / (length * length), 0.0), 1.0)
    return math.hypot(x - ax - s * ux, y - ay - s * uy)


def _in_wedge(px: float, py: float, d: float, cx: float, cy: float, cos_half: float) -> bool:
    return d > 1e-12 and (px * cx + py * cy) >= cos_half * d - 1e-12


# -- factories ------------------------------------------------------------------------


def rectangle(w_m: float, h_m: float, *, name: str = "rectangle") -> World:
    """A w x h rectangle with walls at x = 0, x = w, y = 0, y = h."""
    w, h = float(w_m), float(h_m)
    return World([(0, 0, w, 0), (w, 0, w, h), (w, h, 0, h), (0, h, 0, 0)], name=name)


POOL_LENGTH_M = 25.0
"""Seed 000 §7.3, seed 001 §7: "a rectangular 25 x 8 meters pool"."""
POOL_WIDTH_M = 8.0


def pool(length_m: float = POOL_LENGTH_M, width_m: float = POOL_WIDTH_M) -> World:
    """The pool of seeds 000/001: end walls at x = 0 and x = length, long (side) walls at
    y = 0 and y = width."""
    return rectangle(length_m, width_m, name=f"pool {length_m:g} x {width_m:g} m")


def polygon_segments(points) -> list[tuple[float, float, float, float]]:
    pts = [(float(x), float(y)) for x, y in points]
    return [(*pts[i], *pts[(i + 1) % len(pts)]) for i in range(len(pts))]


def room(w_m: float, h_m: float, obstacles=(), *, name: str = "room") -> World:
    """A rectangular room with convex obstacles, each given as its corner points."""
    segs = rectangle(w_m, h_m).segments()
    for poly in obstacles:
        if len(poly) < 3:
            raise ValueError(f"obstacle {poly!r}: a polygon needs at least 3 corners")
        segs += polygon_segments(poly)
    return World(segs, name=name)


def box(cx: float, cy: float, w: float, h: float) -> list[tuple[float, float]]:
    """Corners of an axis-aligned w x h box centred on (cx, cy)."""
    return [(cx - w / 2, cy - h / 2), (cx + w / 2, cy - h / 2), (cx + w / 2, cy + h / 2), (cx - w / 2, cy + h / 2)]


def vacuum_room() -> World:
    """A 5 x 4 m room with convex furniture, for seed 003's go-to-goal and avoidance."""
    return room(
        5.0,
        4.0,
        [box(3.2, 1.2, 0.4, 0.4), box(1.3, 3.0, 0.6, 0.3), [(3.6, 2.6), (4.2, 2.9), (3.8, 3.4)]],
        name="vacuum room 5 x 4 m",
    )


def duct_network(sections, *, name: str = "duct") -> World:
    """Walls of a rectilinear duct network: the boundary of the union of axis-aligned
    sections ``(x0, y0, x1, y1)``. Edges shared by two sections (the mouth of a branch)
    are open."""
    rects = [(min(x0, x1), min(y0, y1), max(x0, x1), max(y0, y1)) for x0, y0, x1, y1 in sections]
    segs = []
    for i, (x0, y0, x1, y1) in enumerate(rects):
        # each edge: fixed coordinate, span, axis, and the outward side (+1 / -1)
        for fixed, lo, hi, horizontal, out in (
            (y0, x0, x1, True, -1),
            (y1, x0, x1, True, +1),
            (x0, y0, y1, False, -1),
            (x1, y0, y1, False, +1),
        ):
            pieces = [(lo, hi)]
            for j, (ox0, oy0, ox1, oy1) in enumerate(rects):
                if j == i:
                    continue
                if horizontal:
                    n_lo, n_hi, s_lo, s_hi = oy0, oy1, ox0, ox1
                else:
                    n_lo, n_hi, s_lo, s_hi = ox0, ox1, oy0, oy1
                # the other section covers the outward side of this edge there, or has the
                # same edge (overlapping sections: the first one keeps it)
                covers = (n_lo <= fixed < n_hi) if out > 0 else (n_lo < fixed <= n_hi)
                same_edge = j < i and fixed == (n_hi if out > 0 else n_lo)
                if covers or same_edge:
                    pieces = _subtract(pieces, s_lo, s_hi)
            for a, b in pieces:
                if b - a > 1e-9:
                    segs.append((a, fixed, b, fixed) if horizontal else (fixed, a, fixed, b))
    return World(segs, name=name)


def _subtract(pieces, lo, hi):
    result = []
    for a, b in pieces:
        if hi <= a or lo >= b:
            result.append((a, b))
            continue
        if lo > a:
            result.append((a, lo))
        if hi < b:
            result.append((hi, b))
    return result


DUCT_WIDTH_M = 0.4
"""Duct width for the seed 002 worlds (not in the seed; the robot is 200 mm wide)."""


def one_right_branch_duct(width_m: float = DUCT_WIDTH_M) -> World:
    """Seed 002 §5.5–5.8: a straight duct with one branch to the right.

    The main duct runs along +x from x = 0 to 3.0 m (y from 0 to ``width_m``); the branch
    leaves to the right (-y) at x = 1.5 m and runs 1.2 m. Both ends are closed."""
    w = width_m
    return duct_network([(0.0, 0.0, 3.0, w), (1.5, -1.2, 1.5 + w, 0.0)], name="duct with one right branch")


def multi_branch_duct(width_m: float = DUCT_WIDTH_M) -> World:
    """A duct with branches on both sides, one of which branches again (the "complex duct"
    of seed 002 §4.6, whose coordinates the seed does not give).

    Main duct along +x to 5 m; a right branch at x = 1.0 m (1.5 m long); a left branch at
    x = 2.5 m (2.4 m long) with a right sub-branch at y = 1.5 m (1.1 m long); a right
    branch at x = 3.8 m (1.2 m long)."""
    w = width_m
    return duct_network(
        [
            (0.0, 0.0, 5.0, w),
            (1.0, -1.5, 1.0 + w, 0.0),
            (2.5, w, 2.5 + w, 2.4 + w),
            (2.5 + w, 1.5, 3.6 + w, 1.5 + w),
            (3.8, -1.2, 3.8 + w, 0.0),
        ],
        name="duct with nested branches",
    )


CANYON_WIDTH_M = 1.2
CANYON_LEAD_M = 1.5
CANYON_BEND_M = 12.0
CANYON_SHIFT_M = 1.2
CANYON_TAIL_M = 2.0
CANYON_END_M = CANYON_LEAD_M + CANYON_BEND_M + CANYON_TAIL_M
"""Seed 004's S-curve canyon (Fig. 10; its size is lost with the figure): a straight
lead-in, an S that shifts the corridor 1.2 m sideways over 12 m (a left bend, then a
right bend: at most 11.3 degrees off the x axis), a straight tail, open at x = 15.5 m.
The bends are as sharp as the seed's wall follower can take at its 400 mm/s: its heading
lags the wall by v / k = 3.2 m of travel (k = 0.125 /s), which carries the robot towards
the outside of each bend (docs/lab_robot.md)."""


def canyon_centre_m(x_m: float) -> float:
    """The canyon's centre line, y at x (m): 0 along the lead-in, a smooth step of
    ``CANYON_SHIFT_M`` over the bend (zero slope and curvature at both ends), then level."""
    u = min(max((x_m - CANYON_LEAD_M) / CANYON_BEND_M, 0.0), 1.0)
    return CANYON_SHIFT_M * (u - math.sin(2 * math.pi * u) / (2 * math.pi))


def canyon(width_m: float = CANYON_WIDTH_M, *, name: str = "canyon") -> World:
    """Seed 004's S-curve "canyon": a corridor ``width_m`` wide along
    :func:`canyon_centre_m` from x = 0 to ``CANYON_END_M``, walled on both sides,
    closed at the start and open at the far end (wall following stops where no wall is
    seen). Walls are polylines with a vertex every 0.25 m."""
    n = round(CANYON_END_M / 0.25)
    centre = [(CANYON_END_M * i / n, canyon_centre_m(CANYON_END_M * i / n)) for i in range(n + 1)]
    left, right = [], []
    for i, (x, y) in enumerate(centre):
        x2, y2 = centre[min(i + 1, n)]
        x1, y1 = centre[max(i - 1, 0)]
        tx, ty = x2 - x1, y2 - y1
        t = math.hypot(tx, ty)
        nx, ny = -ty / t, tx / t
        left.append((x + nx * width_m / 2, y + ny * width_m / 2))
        right.append((x - nx * width_m / 2, y - ny * width_m / 2))
    segs = [(*left[i], *left[i + 1]) for i in range(n)] + [(*right[i], *right[i + 1]) for i in range(n)]
    segs.append((*right[0], *left[0]))
    return World(segs, name=name)
