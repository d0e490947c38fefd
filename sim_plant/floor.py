"""Reflectance sensors looking at the floor: the engine part behind the catalogue's
``line_sensor`` (and the ``qtr``'s channels), and the floors they look at.

A floor answers one question, how dark it is at a point (:meth:`darkness`: 0 white, 1
black). Two kinds: the body's ``tape``, a path of dark tape (1 on it, 0 beside it), and a
world's picture of the floor (``line_course``: :class:`PictureFloor`, the picture's
darkness between its pixels). A sensor over both sees the darker."""

import math

from sim_plant.engine import Part
from sim_plant.plant import NEVER_US, Change

DARK = 0.5
"""A sensor is over the line (its truth's ``on_tape``) where the floor is at least this dark."""


class TapeFloor:
    """The body's tape: a path of [x, y] points, ``width_m`` wide; dark on it, white beside it."""

    FIXED_STATE = True  # configuration only

    def __init__(self, tape, width_m: float):
        if len(tape) == 1 or any(len(p) != 2 for p in tape):
            raise ValueError("tape: expected a path of [x, y] points (two or more)")
        self.tape = tuple(tuple(float(v) for v in p) for p in tape)
        self.half_width_m = float(width_m) / 2

    def darkness(self, px: float, py: float) -> float:
        for (ax, ay), (bx, by) in zip(self.tape, self.tape[1:]):
            ux, uy = bx - ax, by - ay
            k = max(0.0, min(1.0, ((px - ax) * ux + (py - ay) * uy) / (ux * ux + uy * uy or 1.0)))
            if math.hypot(px - ax - k * ux, py - ay - k * uy) <= self.half_width_m:
                return 1.0
        return 0.0


class PictureFloor:
    """A picture of the floor, ``width`` x ``height`` pixels of ``gray`` (a byte a pixel,
    rows from the picture's top; 0 black, 255 white), ``m_per_px`` metres a pixel, its
    bottom-left corner at the world's (0, 0): x to the right, y up the picture. Pixel
    (col, row)'s centre is at ((col + 0.5) m_per_px, (height - row - 0.5) m_per_px).

    ``bilinear``: the darkness between the four nearest pixel centres, weighted by
    distance (a smooth edge a pixel wide); else the nearest pixel's. Off the picture: white."""

    FIXED_STATE = True  # configuration only (the bytes never change)

    def __init__(self, gray: bytes, width: int, height: int, m_per_px: float, *, bilinear: bool = True):
        if len(gray) != width * height or width < 1 or height < 1:
            raise ValueError(f"picture: expected {width} x {height} bytes, got {len(gray)}")
        self.gray = bytes(gray)
        self.width, self.height = int(width), int(height)
        self.m_per_px = float(m_per_px)
        self.bilinear = bool(bilinear)

    @property
    def size_m(self) -> tuple[float, float]:
        return self.width * self.m_per_px, self.height * self.m_per_px

    def darkness(self, px: float, py: float) -> float:
        u = px / self.m_per_px  # in pixels from the left edge
        v = self.height - py / self.m_per_px  # from the top edge
        if not (0.0 <= u < self.width and 0.0 <= v < self.height):
            return 0.0
        if not self.bilinear:
            return 1.0 - self.gray[int(v) * self.width + int(u)] / 255
        u, v = u - 0.5, v - 0.5  # from the first pixel's centre
        c0, r0 = math.floor(u), math.floor(v)
        fu, fv = u - c0, v - r0
        c0, c1 = max(c0, 0), min(c0 + 1, self.width - 1)  # (the edge pixels extend to the edge)
        r0, r1 = max(r0, 0), min(r0 + 1, self.height - 1)
        g, w = self.gray, self.width
        top = g[r0 * w + c0] * (1 - fu) + g[r0 * w + c1] * fu
        bottom = g[r1 * w + c0] * (1 - fu) + g[r1 * w + c1] * fu
        return 1.0 - (top * (1 - fv) + bottom * fv) / 255


class FloorSensors(Part):
    """Reflectance sensors looking at the floor (TCRT5000 or QTR style, on an ADC): each
    reads ``floor_u16`` over white, ``tape_u16`` over black (dark: little light comes
    back, the output is high) and in proportion between (a picture's grey, its edges).
    The floor is the body's ``tape`` and the world's picture, if it has one (the darker
    of the two). It is checked every ``period_us``; a reading is a change only when it
    changes (a continuous voltage, not a sampled one)."""

    FIXED_STATE = ("offsets", "floors", "inputs", "outputs", "names")

    def __init__(self, offsets, tape, *, width_m, tape_u16, floor_u16, period_us):
        if period_us <= 0:
            raise ValueError(f"floor_period_us: expected > 0, got {period_us}")
        self.offsets = [tuple(float(v) for v in o) for o in offsets]
        self.floors = (TapeFloor(tape, width_m),) if tape else ()
        self.levels = (int(floor_u16), int(tape_u16))
        self.period_us = int(period_us)
        self.names = [f"floor_{i}.adc" for i in range(len(self.offsets))]
        self.outputs = dict.fromkeys(self.names, "u16")
        self.values = [self.levels[0]] * len(self.offsets)
        self.darks = [0.0] * len(self.offsets)  # the floor's darkness under each, as last looked at
        self.next_us = NEVER_US

    def look_at_world(self, plant) -> None:
        """The world's floor too (a picture), under the body's tape: at the start."""
        floor = plant.world.floor if plant.world is not None else None
        if floor is not None and floor not in self.floors:
            self.floors = (*self.floors, floor)

    def start(self, t_us: int, plant) -> None:
        self.look_at_world(plant)
        self.darks = self.dark(plant.pose_at(t_us))
        self.values = self._levels(self.darks)
        self.next_us = self._next_look(t_us)

    def _next_look(self, t_us: int) -> int:
        """When to look again: a period on, or never where there is nothing to see (no
        tape and no picture: the floor is white everywhere, no reading can change)."""
        return t_us + self.period_us if self.floors else NEVER_US

    def initial_outputs(self) -> dict:
        return dict(zip(self.names, self.values))

    def fire(self, t_us: int, plant, out: list) -> None:
        self.darks = self.dark(plant.pose_at(t_us))
        values = self._levels(self.darks)
        for name, old, new in zip(self.names, self.values, values):
            if new != old:
                out.append(Change(t_us, name, new))
        self.values = values
        self.next_us = self._next_look(t_us)

    def _levels(self, darks) -> list[int]:
        """Each reading, from white's level to black's in proportion to the darkness."""
        white, black = self.levels
        return [white if d <= 0.0 else black if d >= 1.0 else round(white + d * (black - white)) for d in darks]

    def dark(self, pose) -> list[float]:
        """The floor's darkness under each sensor at ``pose`` (0 white .. 1 black)."""
        x, y, th = pose
        c, s = math.cos(th), math.sin(th)
        return [self._darkness(x + dx * c - dy * s, y + dx * s + dy * c) for dx, dy in self.offsets]

    def _darkness(self, px: float, py: float) -> float:
        darkest = 0.0
        for floor in self.floors:
            darkest = max(darkest, floor.darkness(px, py))
        return darkest
