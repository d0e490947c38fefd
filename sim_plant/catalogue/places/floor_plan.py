"""World ``floor_plan``: a room drawn as a picture, its walls and furniture dark on a light
floor, as people sketch a flat or a test arena.

The picture (a PNG, any raster picture Pillow reads, or an SVG drawing: read as the
``line_course`` reads its floor, :func:`~sim_plant.catalogue.places.line_course.read_floor`)
lies with its bottom-left corner at the world's (0, 0), x to the right along its bottom edge,
y up it, at its scale (``mm_per_px`` or ``width_m``). Every pixel darker than half
(``wall_below`` of 255, grey) is solid: its edges with the light pixels become walls, merged
into the longest straight runs, so the sonars, rangers and bumpers see the drawing's walls
and obstacles as they see a room's; the picture's own edges are walls too. A slanted or
round wall is a staircase of pixel edges (draw at a centimetre a pixel or finer)."""

from pathlib import Path

import numpy as np

from sim_plant.catalogue.base import Opt, PartsError, WorldType
from sim_plant.catalogue.places.line_course import read_floor
from sim_plant.option_table import POSE, FileName, Num, length
from sim_plant.world import World

MAX_WALLS = 20_000
"""A drawing whose walls come to more than this many segments is refused (a photograph, a
texture): draw the walls as plain shapes."""


class FloorPlan(WorldType):
    kind = "floor_plan"
    doc = (
        "A room drawn as a picture (PNG or SVG): its dark pixels are walls and obstacles, the light ones floor;"
        " scale mm_per_px or width_m, (0, 0) at its bottom-left corner (docs/rig-file.md, 'A room drawn as a picture')."
    )
    OPTIONS = (
        Opt("picture", FileName("a picture's path, relative to the rig file"), None, "the room's picture (PNG or SVG)"),
        Opt(
            "mm_per_px", Num("millimetres", 0.01, 1000, none=True), None, "millimetres a pixel: its scale (or width_m)"
        ),
        Opt("width_m", length(0.01, 100, none=True), None, "its whole width (or mm_per_px): the scale from it"),
        Opt("wall_below", Num("grey level", 1, 255), 128, "a pixel darker than this (0 black, 255 white) is solid"),
        Opt(
            "start_pose",
            POSE,
            None,
            "where the robot starts, from the picture's bottom-left corner (on the floor); its centre by default",
        ),
    )

    def build(self):
        o = self.options
        if o["picture"] is None:
            raise PartsError("[world] picture: expected the room's picture (a PNG or an SVG, relative to the rig file)")
        if (o["mm_per_px"] is None) == (o["width_m"] is None):
            raise PartsError("[world] mm_per_px, width_m: expected the picture's scale, one of them (not both)")
        path = Path(o["picture"])
        gray, width, height, m_per_px = read_floor(path, o["width_m"], o["mm_per_px"])
        solid = np.frombuffer(gray, dtype=np.uint8).reshape(height, width) < o["wall_below"]
        segments = wall_segments(solid, m_per_px)
        if len(segments) > MAX_WALLS:
            raise PartsError(
                f"[world] picture: {path} makes {len(segments):,} wall segments, more than {MAX_WALLS:,} "
                f"(a photograph or a texture?): draw walls and obstacles as plain dark shapes"
            )
        w_m, h_m = width * m_per_px, height * m_per_px
        world = World(segments, name=f"floor plan {w_m:.3g} x {h_m:.3g} m")
        start = o["start_pose"] or (w_m / 2, h_m / 2, 0.0)
        x, y, _ = start
        col, row = int(x / m_per_px), int(height - y / m_per_px)
        if not (0 <= col < width and 0 <= row < height) or solid[row, col]:
            raise PartsError(
                f"[world] start_pose: {list(start)} is not on the drawing's floor "
                f"(off the picture, or on a dark pixel: a wall or an obstacle)"
            )
        return world, tuple(float(v) for v in start)


def wall_segments(solid: np.ndarray, m_per_px: float) -> list[tuple[float, float, float, float]]:
    """The edges between solid and free pixels of ``solid`` (rows from the top), and the
    picture's edges where a free pixel touches them, each straight run as one segment
    (x0, y0, x1, y1) in metres, y up from the bottom edge."""
    height, width = solid.shape
    padded = np.ones((height + 2, width + 2), dtype=bool)  # (outside the picture: solid)
    padded[1:-1, 1:-1] = solid
    segments = []
    # horizontal edges: between rows r and r + 1 of the padded picture, at y = (height - r) m_per_px
    rows = padded[:-1, 1:-1] != padded[1:, 1:-1]
    for r, line in enumerate(rows):
        y = (height - r) * m_per_px
        for a, b in _runs(line):
            segments.append((a * m_per_px, y, b * m_per_px, y))
    # vertical edges: between columns c and c + 1, at x = c m_per_px
    cols = padded[1:-1, :-1] != padded[1:-1, 1:]
    for c, line in enumerate(cols.T):
        x = c * m_per_px
        for a, b in _runs(line):
            segments.append((x, (height - a) * m_per_px, x, (height - b) * m_per_px))
    return segments


def _runs(line: np.ndarray) -> list[tuple[int, int]]:
    """The runs of True in ``line``: (first index, one past the last)."""
    edges = np.flatnonzero(np.diff(np.concatenate(([False], line, [False])).astype(np.int8)))
    return list(zip(edges[::2].tolist(), edges[1::2].tolist()))
