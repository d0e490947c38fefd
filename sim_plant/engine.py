"""The event loop the robot plants share.

Between two events every input is constant, so wheel speeds are constant, the pose
follows an exact arc and each encoder's shaft angle grows linearly: encoder edges fall
at exactly computable integer microseconds and no time step is needed. The loop keeps
the time of the next event of every part and jumps from one to the next.

A plant is made of:

* a **drive** (a :class:`Part` with a ``body``): turns the actuator inputs into wheel
  or track speeds and integrates the pose;
* **encoders** (:mod:`sim_plant.physics.encoder`): edges from the wheel speeds;
* other **parts** with a timeline of their own: sensors, the contact monitor, the
  coverage recorder.

State is plain objects holding numbers, tuples, lists, dicts and arrays (no reference
back to the plant, no stored callables), so that :meth:`RobotPlant.snapshot` can save it
in place and :meth:`RobotPlant.restore` bring it back, for the host's rollback of a
speculative batch of IRQ edges.
"""

import ctypes
import math

import numpy as np

from sim_plant import edge_window
from sim_plant.motors import DcMotor
from sim_plant.plant import NEVER_US, POSE, Change, Plant

SHARED_STATE = frozenset(("rng", "world", "_snapshot_plan", "_raw_rng"))
"""Plant attributes a snapshot leaves alone: the generator (its state is saved instead),
the world (walls do not change; its cache of local views may differ harmlessly) and the
snapshot plan itself (and the generator's copier made with it)."""
_SCALARS = frozenset((int, float, str, bytes, bool, type(None), frozenset))


def _is_object(value) -> bool:
    return hasattr(value, "__dict__") and not isinstance(value, type)


def state_objects(root):
    """Every object of a plant's state: the plant, its parts, their parts... (not what
    it shares: the generator, the world)."""
    seen, todo = set(), [root]
    while todo:
        obj = todo.pop()
        if id(obj) in seen:
            continue
        seen.add(id(obj))
        yield obj
        for key, value in obj.__dict__.items():
            kind = type(value)
            if kind in _SCALARS or key in SHARED_STATE and obj is root:
                continue
            if kind is list or kind is tuple:
                todo.extend(v for v in value if _is_object(v))
            elif kind is dict:
                todo.extend(v for v in value.values() if _is_object(v))
            elif _is_object(value):
                todo.append(value)


def _snapshot_plan(root) -> list:
    """Every object of a plant's state with the names of its attributes that hold
    containers (list, dict, writable array): a snapshot copies each object's attributes,
    and those containers one level deeper. Containers hold numbers, tuples or part
    objects; an attribute that holds a container or a part keeps holding one (an
    attribute that starts as None may later hold only immutables).

    A class names in ``FIXED_STATE`` the containers it fills when it is built and never
    changes afterwards (wiring, routes, its parts): those are not copied, and a class
    whose ``FIXED_STATE`` is True (pure configuration) is left out of the plan."""
    plan = []
    for obj in state_objects(root):
        fixed = getattr(type(obj), "FIXED_STATE", ())
        if fixed is True:
            continue
        containers = []
        for key, value in obj.__dict__.items():
            kind = type(value)
            if key in fixed or key in SHARED_STATE and obj is root:
                continue
            if kind is list or kind is dict or (kind is np.ndarray and value.flags.writeable):
                containers.append(key)
        plan.append((obj, tuple(containers)))
    return plan


def _dicts_of(plan: list) -> tuple:
    """A snapshot plan as a snapshot reads it: each object's ``__dict__`` (copied in one
    comprehension), and where containers are (the object's place, their names)."""
    dicts = tuple(obj.__dict__ for obj, _ in plan)
    return dicts, tuple((i, containers) for i, (_, containers) in enumerate(plan) if containers)


class _RawGenerator:
    """A PCG64 generator's state as raw bytes (its 128-bit state and increment, its
    buffered 32-bit draw), saved and put back as two copies of memory: ``bit_generator.state``
    builds a dict of 128-bit Python ints (some 20,000 instructions a snapshot, a fifth of
    it). :func:`_raw_generator` checks the layout once on the generator itself."""

    __slots__ = ("bit_generator", "_pcg", "_buffered")

    def __init__(self, bit_generator):
        self.bit_generator = bit_generator  # (kept: the arrays are views of its memory)
        at = bit_generator.ctypes.state_address  # a pcg64_state: a pointer, has_uint32, uinteger
        pcg_at = ctypes.c_void_p.from_address(at).value  # a pcg64_random_t: state, inc
        self._pcg = (ctypes.c_char * 32).from_address(pcg_at)
        self._buffered = (ctypes.c_char * 8).from_address(at + ctypes.sizeof(ctypes.c_void_p))

    def save(self) -> tuple:
        return self.bit_generator, self._pcg.raw, self._buffered.raw

    def put(self, saved: tuple) -> None:
        self._pcg.raw = saved[1]
        self._buffered.raw = saved[2]


def _raw_generator(rng):
    """A :class:`_RawGenerator` of ``rng``, or None (another bit generator, or a layout other
    than the one it copies: the generator is then saved as ``bit_generator.state``). The check
    draws from the generator and leaves it as it found it."""
    bit_generator = rng.bit_generator
    if type(bit_generator) is not np.random.PCG64:
        return None
    state = bit_generator.state
    try:
        raw = _RawGenerator(bit_generator)
        saved = raw.save()
        rng.integers(0, 2**32, dtype=np.uint32)  # (a 32-bit draw: the buffered half is set)
        rng.random()
        raw.put(saved)
        same = bit_generator.state == state
    except Exception:  # (no ctypes interface: the dict way)
        same = False
    bit_generator.state = state  # (as found, whatever the check did)
    return raw if same else None


def _put_generator(plant, saved) -> None:
    """The plant's generator as a snapshot saved it (a state dict, or raw bytes)."""
    bit_generator = plant.rng.bit_generator
    if type(saved) is dict:
        bit_generator.state = saved
    elif plant._raw_rng is not None and plant._raw_rng.bit_generator is bit_generator:
        plant._raw_rng.put(saved)
    else:  # (saved from another generator: put back there, then passed on as a dict)
        _RawGenerator(saved[0]).put(saved)
        bit_generator.state = saved[0].state


class Part:
    """Something with a timeline of its own.

    ``next_us`` is the next time the part needs the plant's attention (``NEVER_US``
    when idle); :meth:`fire` does what is due then and appends the output changes.
    ``inputs`` and ``outputs`` map the part's signal names to their kind.
    """

    next_us: int = NEVER_US
    inputs: dict = {}
    outputs: dict = {}
    FIXED_STATE: tuple | bool = ("inputs", "outputs")

    def fire(self, t_us: int, plant: "RobotPlant", out: list) -> None:
        """Handle what is due at ``t_us``; append :class:`Change` s to ``out``."""

    def set_input(self, name: str, value, t_us: int, plant: "RobotPlant") -> bool:
        """Apply an input of this part at ``t_us``; True if the drive's motion may have
        changed (the plant then calls :meth:`settle` once before it moves on)."""
        raise KeyError(name)

    def settle(self, t_us: int, plant: "RobotPlant") -> bool:
        """The inputs set at ``t_us`` are all in: True if the motion changed."""
        return True

    def initial_outputs(self) -> dict:
        """Output values at reset."""
        return {}

    def start(self, t_us: int, plant: "RobotPlant") -> None:
        """Called once at reset, after the whole plant is built."""

    def on_motion_change(self, t_us: int, plant: "RobotPlant") -> None:
        """The drive's speeds changed at ``t_us``: re-plan anything that depended on them."""

    def truth(self, t_us: int, plant: "RobotPlant") -> dict:
        """Ground truth this part knows, at ``t_us`` (reading it changes nothing)."""
        return {}


class RobotPlant(Plant):
    """A plant built from a drive, encoders and timed parts (see the module doc).

    Subclasses implement :meth:`_build`, which sets ``self.world``, ``self.drive``,
    ``self.encoders`` and ``self.parts`` afresh (the generator ``self.rng`` is already
    seeded), and may extend :meth:`truth`.
    """

    FIXED_STATE = ("encoders", "parts", "inputs", "outputs", "_input_route", "_encoder_outputs")
    capabilities = frozenset((POSE,))

    def close(self) -> None:
        for part in self.parts:
            close = getattr(part, "close", None)  # (a part holding a program outside: an external chip)
            if close is not None:
                close()

    def __init__(self):
        self.reset(0)
        self.inputs = {}
        self.outputs = {}
        for part in [self.drive, *self.parts]:
            self.inputs.update(part.inputs)
            self.outputs.update(part.outputs)
        for enc in self.encoders:
            self.outputs.update(dict.fromkeys(enc.names, "level"))

    def _build(self) -> None:
        raise NotImplementedError

    # -- for two-wheeled robots ---------------------------------------------------------

    def _set_wheels(
        self,
        *,
        start_pose,
        wheel_radius_m,
        track_m,
        v_max_m_s,
        deadband_duty,
        motor_gains,
        motor_time_constant_ms,
        bumper,
        bumper_bounce_us,
    ) -> None:
        """Keep the constructor's drive and bumper options, as :meth:`_wheel_motors` and
        the plant's ``_build`` read them."""
        self.start_pose = tuple(float(v) for v in start_pose)
        self.wheel_radius_m = float(wheel_radius_m)
        self.track_m = float(track_m)
        self.v_max_m_s = float(v_max_m_s)
        self.deadband_duty = float(deadband_duty)
        self.motor_gains = tuple(motor_gains)
        self.motor_time_constant_ms = float(motor_time_constant_ms)
        self.bumper = bool(bumper)
        self.bumper_bounce_us = int(bumper_bounce_us)

    def _wheel_motors(self) -> tuple:
        """One DcMotor per wheel from the plant's ``v_max_m_s``, ``wheel_radius_m``,
        ``deadband_duty``, ``motor_gains`` and ``motor_time_constant_ms``."""
        return tuple(
            DcMotor(
                max_wheel_rad_s=self.v_max_m_s / self.wheel_radius_m,
                deadband_duty=self.deadband_duty,
                gain=g,
                time_constant_ms=self.motor_time_constant_ms,
            )
            for g in self.motor_gains
        )

    # -- contract -------------------------------------------------------------------

    def reset(self, seed: int) -> None:
        self.rng = np.random.default_rng(seed)
        self._snapshot_plan = None  # made at the first snapshot after each reset
        self._raw_rng = None  # (the generator's raw copier, found with the plan; None: its dict)
        self._t_us = 0
        self._build()
        route = {name: -1 for name in self.drive.inputs}
        for i, part in enumerate(self.parts):
            route.update(dict.fromkeys(part.inputs, i))
        self._input_route = route
        self.drive.start(0, self)
        for part in self.parts:
            part.start(0, self)
        values = dict(self.drive.initial_outputs())
        for part in self.parts:
            values.update(part.initial_outputs())
        self.values = values  # outputs of the drive and parts (encoders keep their own)
        self._encoder_outputs = {
            name: (i, k) for i, enc in enumerate(self.encoders) for k, name in enumerate(enc.names)
        }
        self._motion_pending = False
        # (whether the encoders' edges have a closed form, :func:`edge_window.plain`: found once, not at each advance)
        self._plain_encoders = edge_window.plain(self.encoders)
        self._motion_changed(0)
        # (a part whose instants may be fired at once, :func:`_fire_alone`: found once, not at each instant)
        self._alone = not self.encoders and not self._reacts() and any(hasattr(p, "fire_until") for p in self.parts)

    @property
    def t_us(self) -> int:
        return self._t_us

    def set_input(self, name: str, value) -> None:
        where = self._input_route.get(name)
        if where is None:
            raise KeyError(f"{type(self).__name__} has no input {name!r}; inputs: {sorted(self._input_route)}")
        part = self.drive if where < 0 else self.parts[where]
        moved = part.set_input(name, value, self._t_us, self)
        if moved:  # re-planned once, when the plant is next asked: a board sets both
            self._motion_pending = True  # wheels' inputs at the same instant
        elif not self._motion_pending:
            self._reschedule()

    def _settle(self) -> None:
        if self._motion_pending:
            self._motion_pending = False
            if self.drive.settle(self._t_us, self):
                self._motion_changed(self._t_us)
            else:
                self._reschedule()

    def next_change_us(self) -> int:
        if self._motion_pending:
            self._settle()
        return self._next_us

    def advance_to(self, t_us: int, limit: int = 0) -> list[Change]:
        return self.advance_edges(t_us, limit, None)

    @property
    def edge_counters(self) -> tuple:
        return tuple(self.encoders) if self.encoders and self._plain_encoders else ()

    def advance_edges(self, t_us: int, limit: int, segs, seg_room: int = 0) -> list[Change]:  # noqa: C901 (the one loop)
        """:meth:`advance_to`; with a list ``segs``, the encoders' edges between two events
        of the other parts go there as segments (``edge_window.segments``: the encoder's
        index, its first edge's time, its count before it, edges, t0_us, p0, rate), not into
        the changes (nor into ``limit``'s count), wherever the closed form holds; it stops
        after the window that takes ``segs`` to ``seg_room`` (0: no limit)."""
        if self._motion_pending:
            self._settle()
        out: list[Change] = []
        nxt = self._next_us
        if nxt <= t_us:
            encoders = self.encoders
            window_at = nxt if self._plain_encoders else NEVER_US
            while nxt <= t_us:
                if nxt >= window_at and self._next_part_us > nxt:
                    # the edges until the next part's event at once (sim_plant/edge_window.py)
                    t_stop = min(t_us, self._next_part_us - 1)
                    if segs is not None:
                        t_last = edge_window.segments(encoders, t_stop, segs)
                    else:
                        t_last = edge_window.emit_window(encoders, t_stop, out, limit)
                    if t_last is None:  # (too few: one by one until the next part's event, emit's loop in one call)
                        t_last, nxt = encoders[0].emit_until(encoders, nxt, t_stop, self._next_part_us, out, limit)
                        stop = limit and len(out) >= limit
                    else:
                        nxt = min(self._next_part_us, *(enc.next_us for enc in encoders))
                        stop = limit and len(out) >= limit or seg_room and len(segs) >= seg_room
                    self._t_us = t_last
                    if stop and nxt > t_last:
                        self._next_us = nxt
                        return out
                    continue
                # everything due at nxt: encoder edges first (they follow the speeds that
                # held until nxt), then the drive, then the other parts in order
                if self._alone and not limit and self._next_part_us == nxt and _fire_alone(self, nxt, t_us, out):
                    nxt = self._next_part_us
                    continue
                self._t_us = nxt
                for enc in encoders:
                    if enc.next_us == nxt:
                        enc.emit(nxt, out)
                if self._next_part_us == nxt:
                    self._fire_parts(nxt, out)
                soonest = self._next_part_us
                for enc in encoders:
                    if enc.next_us < soonest:
                        soonest = enc.next_us
                nxt = soonest
                if limit and len(out) >= limit and nxt > self._t_us:
                    self._next_us = nxt
                    return out  # stopped after the instant that reached the limit
            self._next_us = nxt
        if t_us > self._t_us:
            self._t_us = t_us
        return out

    def output(self, name: str) -> object:
        where = self._encoder_outputs.get(name)
        if where is not None:
            return self.encoders[where[0]].levels[where[1]]
        try:
            return self.values[name]
        except KeyError:
            raise KeyError(f"{type(self).__name__} has no output {name!r}; outputs: {sorted(self.outputs)}") from None

    def truth(self) -> dict:
        if self._motion_pending:
            self._settle()
        x, y, th = self.drive.body.pose_at(self._t_us)
        truth = {"t_us": self._t_us, "x_m": x, "y_m": y, "theta_rad": math.remainder(th, 2 * math.pi)}
        truth.update(self.drive.truth(self._t_us, self))
        for part in self.parts:
            truth.update(part.truth(self._t_us, self))
        for enc in self.encoders:
            truth.update(enc.truth())
        return truth

    # -- snapshots (the host's rollback of a speculative batch) -------------------------

    def snapshot(self):
        """The whole mutable state, to :meth:`restore` later (any number of times): the
        attributes of the plant and of every part object in it, saved in place."""
        plan = self._snapshot_plan
        if plan is None:
            plan = self._snapshot_plan = _dicts_of(_snapshot_plan(self))
            self._raw_rng = _raw_generator(self.rng)
        dicts, deep = plan
        copies = [state.copy() for state in dicts]
        for i, containers in deep:
            attrs = copies[i]
            for key in containers:
                attrs[key] = attrs[key].copy()
        raw = self._raw_rng
        return plan, copies, self.rng.bit_generator.state if raw is None else raw.save()

    def restore(self, snap) -> None:
        (dicts, deep), copies, rng_state = snap
        for state, attrs in zip(dicts, copies):
            state.clear()
            state.update(attrs)
        for i, containers in deep:
            state = dicts[i]
            for key in containers:
                state[key] = state[key].copy()
        _put_generator(self, rng_state)

    # -- loop -----------------------------------------------------------------------

    def pose_at(self, t_us: int) -> tuple[float, float, float]:
        return self.drive.body.pose_at(t_us)

    def _fire_parts(self, t: int, out: list) -> None:
        n0 = len(out)
        drive = self.drive
        if drive.next_us == t:
            drive.fire(t, self, out)
            self._rebase_encoders(t)
            for part in self.parts:
                part.on_motion_change(t, self)
        for part in self.parts:
            if part.next_us == t:
                part.fire(t, self, out)
        if self._react(t):
            self._motion_changed(t)
        values = self.values
        for change in out[n0:]:
            values[change[1]] = change[2]
        self._reschedule()

    def _react(self, t: int) -> bool:
        """Hook after the parts fired at ``t`` (a machine's reaction to its bumpers); True if the motion changed."""
        return False

    _alone = False  # (reset finds whether :func:`_fire_alone` may serve)

    def _reacts(self) -> bool:
        """Whether :meth:`_react` may do anything (else the instants of a part whose events
        are its own can be fired at once: :func:`_fire_alone`)."""
        return type(self)._react is not RobotPlant._react

    def sample_period_us(self, signal: str) -> int | None:
        """How often the part that drives ``signal`` takes a new sample (its
        ``period_us``), or None if it is not sampled at a fixed period."""
        for part in self.parts:
            if signal in part.outputs and isinstance(getattr(part, "period_us", None), int):
                return part.period_us
        return None

    def part(self, cls):
        """The first part of class ``cls`` (for tests and truth)."""
        for p in [self.drive, *self.parts]:
            if isinstance(p, cls):
                return p
        raise LookupError(f"{type(self).__name__} has no {cls.__name__}")

    def _motion_changed(self, t: int) -> None:
        self._rebase_encoders(t)
        for part in self.parts:
            part.on_motion_change(t, self)
        self._reschedule()

    def _rebase_encoders(self, t: int) -> None:
        rates = self.drive.encoder_rad_s()
        for enc in self.encoders:
            enc.set_speed(t, rates[enc.wheel])

    def _reschedule(self) -> None:
        nxt = self.drive.next_us
        for part in self.parts:
            if part.next_us < nxt:
                nxt = part.next_us
        self._next_part_us = nxt
        for enc in self.encoders:
            if enc.next_us < nxt:
                nxt = enc.next_us
        self._next_us = nxt


def _fire_alone(plant: RobotPlant, nxt: int, t_us: int, out: list) -> bool:
    """The one part due at ``nxt`` fired for every instant of its own up to ``t_us``
    in one call, when nothing else is due before the last of them (the drive, another
    part) and the plant does not react at an instant (``plant._alone``, found at reset):
    a ``board_uart``'s bytes, a byte an instant (``fire_until``; the same changes, in the same order, the same values
    and schedule after as an instant at a time). False: fire as ever."""
    other = plant.drive.next_us
    due = None
    for part in plant.parts:
        n = part.next_us
        if n == nxt:
            if due is not None:
                return False
            due = part
        elif n < other:
            other = n
    fire_until = getattr(due, "fire_until", None)
    if fire_until is None or other <= nxt:
        return False
    n0 = len(out)
    last = fire_until(min(t_us, other - 1), out)
    if last is None:
        return False
    plant._t_us = last
    values = plant.values
    for change in out[n0:]:
        values[change[1]] = change[2]
    plant._reschedule()
    return True


__all__ = ["NEVER_US", "Change", "Part", "RobotPlant"]
