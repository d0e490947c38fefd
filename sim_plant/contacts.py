"""Contacts between the body and the walls, and the bumper switches they close.

The body is a set of circles in the body frame (a disc robot is one circle; a long body
is a row of them, like the four circular contact areas of seed 002's simulation, App.
B.4). The :class:`ContactMonitor` checks the circles against the walls at check points
it plans itself: while the body is clear, after the time it needs at full speed to cover
the smallest gap (so a contact is never missed); while it touches, every
``RECHECK_US``. A circle that has gone into a wall is pushed back out along the wall's
normal and held on the wall by a half-plane constraint: the robot stops at the wall or
slides along it while its wheels keep turning.

Every new touch is recorded in the ground truth as a :class:`Contact`. A
:class:`Bumper` is pressed when a touch falls inside its arc; its output level is active
low by default and may bounce.
"""

import math
from typing import NamedTuple

from sim_plant.engine import Part
from sim_plant.plant import NEVER_US, Change

CONTACT_EPS_M = 1e-6
"""A circle closer than this to a wall touches it."""
RECHECK_US = 5_000
"""Check period while touching (release of a bumper is seen within this)."""
MIN_STEP_US = 1_000
"""Closest spacing of check points while approaching a wall."""
PUSH_ITERATIONS = 4
NEAR_REACH_M = 1.0
"""Walls farther than this from a body circle are not looked at: a gap reads at most this."""


def _pushing_square_on(body) -> bool:
    """The body drives straight into the walls it touches, square on: it stays put until
    its speeds change (which re-plans the checks), so no recheck is needed meanwhile."""
    if body.segment is not None or body.w != 0.0 or not body.constraints:
        return False
    vx, vy = math.cos(body.th0), math.sin(body.th0)
    if body.v < 0.0:
        vx, vy = -vx, -vy
    return all(vx * nx + vy * ny < -0.999999 for nx, ny, _c, _ox, _oy in body.constraints)


class Contact(NamedTuple):
    """Ground truth: at ``t_us`` the body touched a wall at pose (x, y); ``part`` is the
    bumper it pressed, or ``"body"``."""

    t_us: int
    x_m: float
    y_m: float
    part: str


class Bumper:
    """A switch over an arc of the body's outline.

    ``circles``: indices of the body circles it covers; ``center_deg``/``half_arc_deg``:
    the arc, from the heading (0 = front, 180 = rear); ``bounce_us``: contact bounce
    window after each press and release (0 = clean); ``bounce_max_pairs``: up to this many
    extra open/close pairs within it.
    """

    def __init__(self, name: str, *, circles=(0,), center_deg: float = 0.0, half_arc_deg: float = 70.0,
                 active_low: bool = True, bounce_us: int = 0, bounce_max_pairs: int = 3):
        self.name = name
        self.circles = tuple(circles)
        self.center_rad = math.radians(center_deg)
        self.half_arc_rad = math.radians(half_arc_deg)
        self.active_low = active_low
        self.bounce_us = int(bounce_us)
        self.bounce_max_pairs = int(bounce_max_pairs)
        self.pressed = False
        self.level = 1 if active_low else 0
        self.pending: list[tuple[int, int]] = []
        self.presses = 0

    def level_for(self, pressed: bool) -> int:
        return int(pressed != self.active_low)

    def set_pressed(self, t_us: int, pressed: bool, rng, out: list) -> None:
        if pressed == self.pressed:
            return
        self.pressed = pressed
        self.presses += pressed
        new = self.level_for(pressed)
        self.pending = []
        if new != self.level:
            self.level = new
            out.append(Change(t_us, self.name, new))
        if self.bounce_us > 0 and self.bounce_max_pairs > 0:
            pairs = int(rng.integers(1, self.bounce_max_pairs + 1))
            draws = rng.choice(self.bounce_us, size=min(2 * pairs, self.bounce_us), replace=False)
            times = sorted(int(v) for v in draws)
            times = times[: len(times) // 2 * 2]
            self.pending = [(t_us + 1 + dt, new ^ 1 if k % 2 == 0 else new) for k, dt in enumerate(times)]


class ContactMonitor(Part):
    """Body circles ``(ox_m, oy_m, r_m)`` against the world's walls, and the bumpers."""

    def __init__(self, circles, bumpers=()):
        self.circles = tuple((float(ox), float(oy), float(r)) for ox, oy, r in circles)
        if not self.circles:
            raise ValueError("ContactMonitor: the body needs at least one circle")
        self.reach_m = max(math.hypot(ox, oy) + r for ox, oy, r in self.circles)
        self.bumpers = list(bumpers)
        self.outputs = {b.name: "level" for b in self.bumpers}
        self.touching: tuple = ()  # (circle, wall normal) pairs in contact at the last check
        self.contacts: list[Contact] = []
        self.check_us = 0
        self.next_us = 0

    def initial_outputs(self) -> dict:
        return {b.name: b.level for b in self.bumpers}

    def start(self, t_us: int, plant) -> None:
        """First check at reset: the bumper levels it finds are the initial outputs."""
        self._check(t_us, plant, [], initial=True)
        self._plan()

    def fire(self, t_us: int, plant, out: list) -> None:
        for b in self.bumpers:
            while b.pending and b.pending[0][0] <= t_us:
                _, level = b.pending.pop(0)
                if level != b.level:
                    b.level = level
                    out.append(Change(t_us, b.name, level))
        if self.check_us <= t_us:
            self._check(t_us, plant, out)
        self._plan()

    def on_motion_change(self, t_us: int, plant) -> None:
        """New speeds: a check planned for the old ones may now come too late (never too
        early: an early check is only a wasted one), so plan again and keep the sooner."""
        x, y, th = plant.drive.body.pose_at(t_us)
        check_us = self._next_check_us(t_us, plant, self._clear_gap(plant.world, x, y, th))
        if check_us < self.check_us:
            self.check_us = check_us
        self._plan()

    def _plan(self) -> None:
        nxt = self.check_us
        for b in self.bumpers:
            if b.pending and b.pending[0][0] < nxt:
                nxt = b.pending[0][0]
        self.next_us = nxt

    def _walls(self, world, x: float, y: float, th: float) -> list[tuple[list, float]]:
        """Per circle: the walls it touches (``(gap, nx, ny)``), and its gap to the others."""
        co, si = math.cos(th), math.sin(th)
        local = world.near(x, y, NEAR_REACH_M + self.reach_m)
        found = []
        for ox, oy, r in self.circles:
            touches, clear = local.circle_walls(x + co * ox - si * oy, y + si * ox + co * oy, r, CONTACT_EPS_M)
            found.append((touches, min(clear, NEAR_REACH_M - r)))
        return found

    def _clear_gap(self, world, x: float, y: float, th: float) -> float:
        return min(clear for _, clear in self._walls(world, x, y, th))

    def _next_check_us(self, t_us: int, plant, clear_gap_m: float) -> int:
        """When the body may first reach a wall it does not touch yet (at full speed), or
        ``RECHECK_US`` while it touches one; never, at rest."""
        body = plant.drive.body
        speed = body.speed_bound_m_s(self.reach_m)
        if speed <= 0.0:
            return NEVER_US
        t = t_us + max(MIN_STEP_US, int(clear_gap_m / speed * 1e6))
        if not self.touching or _pushing_square_on(body):
            return t
        return min(t, t_us + RECHECK_US)

    def _check(self, t_us: int, plant, out: list, initial: bool = False) -> None:
        body, world = plant.drive.body, plant.world
        x, y, th = body.pose_at(t_us)
        for _ in range(PUSH_ITERATIONS):  # push the body out of the walls it went into
            depth, px, py = 0.0, 0.0, 0.0
            for touches, _ in self._walls(world, x, y, th):
                for gap, nx, ny in touches:
                    if -gap > depth:
                        depth, px, py = -gap, nx, ny
            if depth <= 0.0:
                break
            x, y = x + depth * px, y + depth * py
        body.rebase(t_us, (x, y, th))
        co, si = math.cos(th), math.sin(th)
        constraints, touching, clear_gap = [], [], math.inf
        for i, (touches, clear) in enumerate(self._walls(world, x, y, th)):
            ox, oy, _ = self.circles[i]
            qx, qy = x + co * ox - si * oy, y + si * ox + co * oy
            for gap, nx, ny in touches:
                constraints.append((nx, ny, nx * qx + ny * qy - gap, ox, oy))  # on the wall itself
                touching.append((i, round(nx, 3), round(ny, 3), math.atan2(-ny, -nx) - th))
            clear_gap = min(clear_gap, clear)
        body.constraints = tuple(constraints)
        before = self.touching
        self.touching = tuple(key[:3] for key in touching)
        for b in self.bumpers:
            pressed = any(self._in_arc(b, i, a) for i, _, _, a in touching)
            if initial:
                b.pressed, b.level = pressed, b.level_for(pressed)
            else:
                b.set_pressed(t_us, pressed, plant.rng, out)
        for i, nx, ny, a in touching:
            if (i, nx, ny) not in before:
                part = next((b.name for b in self.bumpers if self._in_arc(b, i, a)), "body")
                self.contacts.append(Contact(t_us, x, y, part))
        self.check_us = self._next_check_us(t_us, plant, clear_gap)

    @staticmethod
    def _in_arc(bumper: "Bumper", circle: int, angle_rad: float) -> bool:
        return circle in bumper.circles and \
            abs(math.remainder(angle_rad - bumper.center_rad, 2 * math.pi)) <= bumper.half_arc_rad

    def truth(self, t_us: int, plant) -> dict:
        return {"contacts": list(self.contacts), "touching": bool(self.touching),
                **{f"{b.name}_pressed": b.pressed for b in self.bumpers}}
