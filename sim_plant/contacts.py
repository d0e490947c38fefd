"""Contacts between the body and the walls, and the bumper switches they close.

The body is a set of circles in the body frame (a disc robot is one circle; a long body
is a row of them, like the four circular contact areas of seed 002's simulation, App.
B.4). The :class:`ContactMonitor` checks the circles against the walls at check points
it plans itself: after the time the body needs at full speed to cover the smallest gap
(so a contact is never missed) and, while it touches, no later than the touch can end:
when the touching circle's free motion turns away from the wall, when the touch point reaches
the wall's end, or when it crosses the edge of a bumper's arc; every ``RECHECK_US`` where
that is not worked out (a touch on a corner point, several touches at once while
sliding). A circle that has gone into a wall is pushed back out along the wall's
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
"""Check period while touching where the end of the touch is not worked out in advance,
and after a touching circle starts to move off its wall (its release is seen within this)."""
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


def _release_s(nx: float, ny: float, rx: float, ry: float, v: float, w: float, th: float, recheck_s: float) -> float:
    """When a circle pushed against one wall (normal ``n`` towards the circle) comes off
    it: when its centre's free velocity (at ``(rx, ry)`` from the reference point, on the
    arc ``(v, w)`` from heading ``th``) stops pointing into the wall; never if the centre
    stays put or runs straight into or along it. ``recheck_s`` if it already points away
    or along a turn.

    The centre turns about the instantaneous centre of rotation, ``q`` away from it; after
    a turn ``a = w t`` its free path has gone ``f(a) = A (cos a - 1) + B sin a`` along
    ``n``, with ``A = n . q`` and ``B = n . perp(q)``. ``f`` falls from 0, bottoms out and
    comes back to 0 at ``tan(a / 2) = B / A``: the velocity turns away at half that turn."""
    cvx = v * math.cos(th) - w * ry  # the centre's velocity now
    cvy = v * math.sin(th) + w * rx
    into = nx * cvx + ny * cvy
    if abs(cvx) + abs(cvy) < 1e-12 or (w == 0.0 and into <= 0.0):
        return math.inf  # turning about the centre itself, or a straight line into or along the wall
    if into >= 0.0:
        return recheck_s
    qx, qy = rx + v / w * math.sin(th), ry - v / w * math.cos(th)
    turn = 2.0 * math.atan2(-nx * qy + ny * qx, nx * qx + ny * qy)
    turn = turn % (2.0 * math.pi) if w > 0.0 else -turn % (2.0 * math.pi)
    return (turn or 2.0 * math.pi) / 2.0 / abs(w)


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
    extra open/close pairs within it; ``wired`` False: no output line of its own (what it
    says is read by another part: a bump sensor's flap, ``sim_plant.catalogue.qtr``).
    """

    def __init__(
        self,
        name: str,
        *,
        circles=(0,),
        center_deg: float = 0.0,
        half_arc_deg: float = 70.0,
        active_low: bool = True,
        bounce_us: int = 0,
        bounce_max_pairs: int = 3,
        wired: bool = True,
    ):
        self.name = name
        self.wired = wired
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
            if self.wired:
                out.append(Change(t_us, self.name, new))
        if self.bounce_us > 0 and self.bounce_max_pairs > 0:
            pairs = int(rng.integers(1, self.bounce_max_pairs + 1))
            draws = rng.choice(self.bounce_us, size=min(2 * pairs, self.bounce_us), replace=False)
            times = sorted(int(v) for v in draws)
            times = times[: len(times) // 2 * 2]
            self.pending = [(t_us + 1 + dt, new ^ 1 if k % 2 == 0 else new) for k, dt in enumerate(times)]


def front_bumper(half_arc_deg: float, bounce_us: int) -> "Bumper":
    """A bumper named ``bumper`` over the front of the first body circle."""
    return Bumper("bumper", circles=(0,), center_deg=0.0, half_arc_deg=half_arc_deg, bounce_us=bounce_us)


class ContactMonitor(Part):
    """Body circles ``(ox_m, oy_m, r_m)`` against the world's walls, and the bumpers.

    Check points are planned from what is known at the last check: the ``room`` (the
    smallest gap to a wall not touched, and the distance from each touch point to the end
    of its wall), spent at most at the body's speed bound, and, while touching, how long
    the touches hold at the present speeds (:meth:`_hold_s`). A change of speeds plans
    again from the room left, without looking at the walls.
    """

    FIXED_STATE = ("bumpers", "inputs", "outputs")

    def __init__(self, circles, bumpers=()):
        self.circles = tuple((float(ox), float(oy), float(r)) for ox, oy, r in circles)
        if not self.circles:
            raise ValueError("ContactMonitor: the body needs at least one circle")
        self.reach_m = max(math.hypot(ox, oy) + r for ox, oy, r in self.circles)
        self.bumpers = list(bumpers)
        self.outputs = {b.name: "level" for b in self.bumpers if b.wired}
        self.touching: tuple = ()  # (circle, wall normal) pairs in contact at the last check
        self.contacts: list[Contact] = []
        self.check_us = 0
        self.next_us = 0
        self._touches: tuple = ()  # (circle, nx, ny, run_m) at the last check
        self._room_m = 0.0  # distance no body point can travel before a contact may change,
        self._room_t_us = 0  # as of this time,
        self._rate_m_s = 0.0  # spent at most at this speed since then

    def initial_outputs(self) -> dict:
        return {b.name: b.level for b in self.bumpers if b.wired}

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
                    if b.wired:
                        out.append(Change(t_us, b.name, level))
        if self.check_us <= t_us:
            self._check(t_us, plant, out)
        self._plan()

    def on_motion_change(self, t_us: int, plant) -> None:
        """New speeds: a check planned for the old ones may now come too late (never too
        early: an early check is only a wasted one), so plan again from the room left and
        keep the sooner."""
        self._room_m = max(0.0, self._room_m - self._rate_m_s * (t_us - self._room_t_us) * 1e-6)
        self._room_t_us = t_us
        check_us = self._next_check_us(t_us, plant)
        if check_us < self.check_us:
            self.check_us = check_us
        self._plan()

    def recheck(self, t_us: int) -> None:
        """The world changed at ``t_us`` (an obstacle was placed): check the walls then,
        whatever was planned from the old ones."""
        self.check_us = t_us
        self._room_m = 0.0
        self._room_t_us = t_us
        self._plan()

    def _plan(self) -> None:
        nxt = self.check_us
        for b in self.bumpers:
            if b.pending and b.pending[0][0] < nxt:
                nxt = b.pending[0][0]
        self.next_us = nxt

    def _walls(self, world, x: float, y: float, th: float) -> list[tuple[list, float]]:
        """Per circle: the walls it touches (``(gap, nx, ny, run)``), and its gap to the others."""
        co, si = math.cos(th), math.sin(th)
        local = world.near(x, y, NEAR_REACH_M + self.reach_m)
        found = []
        for ox, oy, r in self.circles:
            touches, clear = local.circle_walls(x + co * ox - si * oy, y + si * ox + co * oy, r, CONTACT_EPS_M)
            found.append((touches, min(clear, NEAR_REACH_M - r)))
        return found

    def _next_check_us(self, t_us: int, plant) -> int:
        """When a contact may first change at the present speeds: the room spent at full
        speed, or the touches' hold; never, at rest. Under ``k`` wall constraints a body
        point moves at most ``1 + k`` times the free speed bound (each push out of a wall
        is at most the free motion of the pushed point)."""
        body = plant.drive.body
        rate = body.speed_bound_m_s(self.reach_m) * (1 + len(body.constraints))
        self._rate_m_s = rate
        if rate <= 0.0:
            return NEVER_US
        dt_s = self._room_m / rate
        if self._touches:  # (the hold is worked out from a base pose at t_us)
            dt_s = min(dt_s, self._hold_s(body) if body.t0_us == t_us else RECHECK_US * 1e-6)
        if dt_s * 1e6 >= NEVER_US - t_us:
            return NEVER_US
        return t_us + max(MIN_STEP_US, int(dt_s * 1e6))

    def _hold_s(self, body) -> float:
        """How long the touches of the last check stay as they are at the body's present
        speeds (the room aside): until a lone touching circle comes off its wall
        (:func:`_release_s`) or a touch point crosses the edge of a bumper's arc (its
        angle from the heading turns at the body's turn rate). ``RECHECK_US`` for a touch
        on a wall's end point, a track-stop segment, or several touches not all square on."""
        recheck_s = RECHECK_US * 1e-6
        touches = self._touches
        if body.segment is not None or (len(touches) > 1 and not _pushing_square_on(body)):
            return recheck_s
        v, w, th = body.v, body.w, body.th0
        co, si = math.cos(th), math.sin(th)
        hold = math.inf
        for i, nx, ny, run in touches:
            if run <= 0.0:
                return recheck_s
            ox, oy, _ = self.circles[i]
            if len(touches) == 1:
                hold = min(hold, _release_s(nx, ny, co * ox - si * oy, si * ox + co * oy, v, w, th, recheck_s))
            if w != 0.0:
                angle = math.atan2(-ny, -nx) - th
                for b in self.bumpers:
                    if i in b.circles:
                        off = abs(math.remainder(angle - b.center_rad, 2 * math.pi))
                        hold = min(hold, abs(off - b.half_arc_rad) / abs(w))
        return hold

    def _check(self, t_us: int, plant, out: list, initial: bool = False) -> None:
        body, world = plant.drive.body, plant.world
        x, y, th = body.pose_at(t_us)
        found = self._walls(world, x, y, th)
        for _ in range(PUSH_ITERATIONS):  # push the body out of the walls it went into
            depth, px, py = 0.0, 0.0, 0.0
            for touches, _ in found:
                for gap, nx, ny, _run in touches:
                    if -gap > depth:
                        depth, px, py = -gap, nx, ny
            if depth <= 0.0:
                break
            x, y = x + depth * px, y + depth * py
            found = self._walls(world, x, y, th)
        body.rebase(t_us, (x, y, th))
        co, si = math.cos(th), math.sin(th)
        constraints, touching, kept, room = [], [], [], math.inf
        for i, (touches, clear) in enumerate(found):
            ox, oy, _ = self.circles[i]
            qx, qy = x + co * ox - si * oy, y + si * ox + co * oy
            for gap, nx, ny, run in touches:
                constraints.append((nx, ny, nx * qx + ny * qy - gap, ox, oy))  # on the wall itself
                touching.append((i, round(nx, 3), round(ny, 3), math.atan2(-ny, -nx) - th))
                kept.append((i, nx, ny, run))
                if run > 0.0:
                    room = min(room, run)
            room = min(room, clear)
        body.constraints = tuple(constraints)
        before = self.touching
        self.touching = tuple(key[:3] for key in touching)
        self._touches = tuple(kept)
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
        self._room_m, self._room_t_us = room, t_us
        self.check_us = self._next_check_us(t_us, plant)

    @staticmethod
    def _in_arc(bumper: "Bumper", circle: int, angle_rad: float) -> bool:
        return (
            circle in bumper.circles
            and abs(math.remainder(angle_rad - bumper.center_rad, 2 * math.pi)) <= bumper.half_arc_rad
        )

    def truth(self, t_us: int, plant) -> dict:
        truth = {"contacts": list(self.contacts), "touching": bool(self.touching)}
        for b in self.bumpers:  # (a loop, not a comprehension: ground truth asks every 50 ms)
            truth[f"{b.name}_pressed"] = b.pressed
        return truth
