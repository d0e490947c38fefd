"""Rooms with convex furniture drawn from a seeded generator, for seed 003's claim that
go-to-goal and obstacle avoidance "can navigate in any convex environment" (§5.1.1).

A room is given a *route* (the start and the goals, in metres): one piece stands across
each leg longer than ``MIN_LEG_M`` (near its middle, a little to one side), so that every
leg needs avoiding, and ``extra`` pieces stand anywhere. Pieces are convex: boxes (a bin,
a chair seat) and regular polygons of 3 to 8 sides (a stool, a round table), turned at
random. Every piece keeps ``gap_m`` from the walls and from the other pieces (the robot is
0.25 m across), and ``clear_m`` from every route point.

=====================  ======  ==========================================================
constant               value   meaning
=====================  ======  ==========================================================
``BOX_SIDE_M``         0.25..0.5  side lengths of a box
``POLYGON_RADIUS_M``   0.15..0.3  corner radius of a polygon
``ACROSS_M``           0.15    how far off the leg's line a leg's piece may stand
=====================  ======  ==========================================================
"""

import math

from sim_plant.world import World, room

BOX_SIDE_M = (0.25, 0.5)
POLYGON_RADIUS_M = (0.15, 0.3)
ACROSS_M = 0.15
MIN_LEG_M = 1.2
ATTEMPTS = 200
DEFAULT_ROUTE = ((0.6, 1.0), (4.2, 1.1), (4.0, 3.0), (1.0, 2.9))
"""A tour of the 5 x 4 m room: start, then three goals."""


def _piece(rng, cx: float, cy: float) -> tuple[list[tuple[float, float]], float]:
    """A convex piece centred on (cx, cy): its corners and its corner radius."""
    turn = rng.uniform(0.0, math.pi)
    if rng.uniform() < 0.5:
        w, h = rng.uniform(*BOX_SIDE_M), rng.uniform(*BOX_SIDE_M)
        local = [(-w / 2, -h / 2), (w / 2, -h / 2), (w / 2, h / 2), (-w / 2, h / 2)]
    else:
        n, r = int(rng.integers(3, 9)), rng.uniform(*POLYGON_RADIUS_M)
        local = [(r * math.cos(2 * math.pi * k / n), r * math.sin(2 * math.pi * k / n)) for k in range(n)]
    c, s = math.cos(turn), math.sin(turn)
    corners = [(cx + c * x - s * y, cy + s * x + c * y) for x, y in local]
    return corners, max(math.hypot(x, y) for x, y in local)


def _fits(cx, cy, r, placed, route, w_m, h_m, gap_m, clear_m) -> bool:
    if min(cx, cy, w_m - cx, h_m - cy) < r + gap_m:
        return False
    if any(math.hypot(cx - px, cy - py) < r + clear_m for px, py in route):
        return False
    return all(math.hypot(cx - qx, cy - qy) >= r + qr + gap_m for qx, qy, qr in placed)


def furnished_room(
    rng,
    route=DEFAULT_ROUTE,
    *,
    room_w_m: float = 5.0,
    room_h_m: float = 4.0,
    extra: int = 2,
    gap_m: float = 0.5,
    clear_m: float = 0.5,
) -> World:
    """A room_w_m x room_h_m room furnished along ``route`` from the generator ``rng``."""
    route = [(float(x), float(y)) for x, y in route]
    placed: list[tuple[float, float, float]] = []
    pieces = []

    def place(where) -> None:
        for _ in range(ATTEMPTS):
            cx, cy = where()
            corners, r = _piece(rng, cx, cy)
            if _fits(cx, cy, r, placed, route, room_w_m, room_h_m, gap_m, clear_m):
                placed.append((cx, cy, r))
                pieces.append(corners)
                return

    for (ax, ay), (bx, by) in zip(route, route[1:]):
        length = math.hypot(bx - ax, by - ay)
        if length < MIN_LEG_M:
            continue
        nx, ny = -(by - ay) / length, (bx - ax) / length

        def on_leg(ax=ax, ay=ay, bx=bx, by=by, nx=nx, ny=ny):
            t, off = rng.uniform(0.35, 0.65), rng.uniform(-ACROSS_M, ACROSS_M)
            return ax + t * (bx - ax) + off * nx, ay + t * (by - ay) + off * ny

        place(on_leg)
    for _ in range(extra):
        place(lambda: (rng.uniform(0.0, room_w_m), rng.uniform(0.0, room_h_m)))
    return room(room_w_m, room_h_m, pieces, name=f"furnished room {room_w_m:g} x {room_h_m:g} m, {len(pieces)} pieces")
