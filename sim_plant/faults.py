"""Faults as data: a schedule of ``[[faults]]`` (a rig file's, or a campaign's scenario
file's), checked, and applied to any plant by wrapping it (``docs/campaigns.md``).

Each fault is a table with a ``kind`` and that kind's fields; times are simulated
seconds, rates are chances per event (0..1). Every fault draws from a stream of its own,
seeded from the run's seed and the fault's place in the schedule, so adding a fault
leaves the others' draws (and the plant's own) as they were.

================  =====================================================================
kind              what the firmware sees
================  =====================================================================
``dropout``       ``signal`` gives nothing in [``start_s``, ``end_s``): no ADC samples, no
                  UART bytes, a level held (then the true level at the end)
``stuck``         ``signal`` reads ``value`` in the window (an ADC's samples, or a level)
``wrong``         an ADC ``signal`` reads ``value * scale + offset`` in the window
``noise``         an ADC ``signal`` gets N(0, ``sd``) counts added in the window
``missed_edges``  each edge of a level ``signal`` is lost with chance ``rate``, with the
                  next one (a pulse the input never saw)
``extra_edges``   after each edge of a level ``signal``, with chance ``rate``, a glitch
                  pulse ``width_us`` long within ``spread_us``
``bounce``        after each edge of a level ``signal`` (a bumper), 1..``pairs`` bounces
                  within ``bounce_ms``
``wheel_slip``    in the window the ``wheel`` (left/right) slips: the ground moves
                  ``1 - slip`` of its turn, its encoder counts all of it
``stuck_wheel``   in the window the ``wheel`` is jammed: it does not turn
``tether_snag``   at each spin on the spot, with chance ``rate``, the tether catches and
                  pulls the body back (:mod:`sim_plant.physics.tether`)
``link_corrupt``  the link's frames are damaged with chance ``rate`` per frame,
                  ``direction`` to_firmware, from_firmware or both (:mod:`host.link.faults`)
``link_stall``    the link stops for ``stall_ms`` before a frame with chance ``rate``
``brownout``      the board loses power at ``at_s`` and boots again (the plant runs on)
``heap``          the interpreter's heap is ``size`` (``64K``), as on a smaller board
================  =====================================================================

The first seven act on the plant's outputs; ``wheel_slip``, ``stuck_wheel`` and
``tether_snag`` are parts added to a robot plant; the last four belong to the harness
(:func:`harness_faults` hands them over) and leave the plant alone.
"""

import heapq
import re
from typing import NamedTuple

import numpy as np

from sim_plant.catalogue.tether import TetherSnag
from sim_plant.engine import Part
from sim_plant.names import nearest
from sim_plant.plant import NEVER_US, Change, Plant

FOREVER_S = 1e9
_REQUIRED = object()
_NUM = (int, float)
_WINDOW = {"start_s": (_NUM, 0.0, (0.0, FOREVER_S)), "end_s": (_NUM, FOREVER_S, (0.0, FOREVER_S))}
_SIGNAL = {"signal": (str, _REQUIRED, None)}
_RATE = {"rate": (_NUM, _REQUIRED, (0.0, 1.0))}
_WHEEL = {"wheel": (str, _REQUIRED, ("left", "right"))}
_DIRECTION = {"direction": (str, "both", ("to_firmware", "from_firmware", "both"))}
KINDS = {
    "dropout": {**_SIGNAL, **_WINDOW},
    "stuck": {**_SIGNAL, **_WINDOW, "value": (int, _REQUIRED, (0, 65535))},
    "wrong": {**_SIGNAL, **_WINDOW, "offset": (int, 0, (-65535, 65535)), "scale": (_NUM, 1.0, (0.0, 100.0))},
    "noise": {**_SIGNAL, **_WINDOW, "sd": (_NUM, _REQUIRED, (0.0, 65535.0))},
    "missed_edges": {**_SIGNAL, **_WINDOW, **_RATE},
    "extra_edges": {
        **_SIGNAL,
        **_WINDOW,
        **_RATE,
        "width_us": (int, 20, (1, 100_000)),
        "spread_us": (int, 500, (1, 1_000_000)),
    },
    "bounce": {**_SIGNAL, **_WINDOW, "bounce_ms": (_NUM, 2.0, (0.001, 100.0)), "pairs": (int, 3, (1, 20))},
    "wheel_slip": {**_WHEEL, **_WINDOW, "slip": (_NUM, _REQUIRED, (0.0, 0.99))},
    "stuck_wheel": {**_WHEEL, **_WINDOW},
    "tether_snag": {
        **_WINDOW,
        **_RATE,
        "pull_m": (_NUM, 0.08, (0.0, 1.0)),
        "twist_deg": (_NUM, 25.0, (0.0, 180.0)),
        "delay_ms": (_NUM, 150.0, (0.0, 10_000.0)),
    },
    "link_corrupt": {**_DIRECTION, **_RATE},
    "link_stall": {**_DIRECTION, **_RATE, "stall_ms": (_NUM, 20.0, (0.0, 4_000.0))},
    "brownout": {"at_s": (_NUM, _REQUIRED, (0.0, FOREVER_S))},
    "heap": {"size": (str, _REQUIRED, None)},
}
SIGNAL_KINDS = {"dropout", "stuck", "wrong", "noise", "missed_edges", "extra_edges", "bounce"}
PART_KINDS = {"wheel_slip", "stuck_wheel", "tether_snag"}
HARNESS_KINDS = {"link_corrupt", "link_stall", "brownout", "heap"}
SIGNAL_TYPES = {  # which output kinds (sim_plant.plant) each signal fault works on
    "dropout": ("level", "u16", "bytes"),
    "stuck": ("level", "u16"),
    "wrong": ("u16",),
    "noise": ("u16",),
    "missed_edges": ("level",),
    "extra_edges": ("level",),
    "bounce": ("level",),
}
_TYPE_NAMES = {str: "text", int: "an integer", bool: "true/false"}


class FaultError(ValueError):
    """A fault schedule that cannot be run: the message names the fault and the field."""


class Fault(NamedTuple):
    """One scheduled fault: its place in the schedule (``index``, the key of its random
    stream), its kind and its fields (defaults filled in)."""

    index: int
    kind: str
    fields: dict

    def __getattr__(self, name):
        try:
            return self.fields[name]
        except KeyError:
            raise AttributeError(name) from None

    def active(self, t_us: int) -> bool:
        return self.fields.get("start_s", 0.0) * 1e6 <= t_us < self.fields.get("end_s", FOREVER_S) * 1e6

    def label(self) -> str:
        """``stuck sonar_f.adc`` / ``tether_snag``: for tables and messages."""
        what = self.fields.get("signal") or self.fields.get("wheel") or self.fields.get("direction")
        return f"{self.kind} {what}" if what else self.kind


def parse_faults(entries) -> tuple[Fault, ...]:
    """A schedule (a list of tables) checked whole: unknown kinds and fields, missing or
    mistyped fields, values out of range and windows that end before they start raise
    :class:`FaultError` naming ``faults[i]`` and the field."""
    if not isinstance(entries, list):
        raise FaultError(f"faults: expected an array of tables ([[faults]]), got {entries!r}")
    return tuple(_parse_one(i, entry) for i, entry in enumerate(entries))


def _hint(word, choices) -> str:
    close = nearest(word, choices)
    return f"; did you mean {' or '.join(map(repr, close))}?" if close else ""


def _parse_one(i: int, entry) -> Fault:
    where = f"faults[{i}]"
    if not isinstance(entry, dict):
        raise FaultError(f"{where}: expected a table, got {entry!r}")
    kind = entry.get("kind")
    if not isinstance(kind, str) or kind not in KINDS:
        raise FaultError(f"{where} kind: expected one of {', '.join(KINDS)}, got {kind!r}{_hint(kind, KINDS)}")
    spec = KINDS[kind]
    fields = {}
    for name, value in entry.items():
        if name == "kind":
            continue
        if name not in spec:
            known = f"(fields of {kind}: {', '.join(spec)}){_hint(name, spec)}"
            raise FaultError(f"{where} ({kind}) {name}: unknown field {known}")
        fields[name] = _check_field(f"{where} ({kind}) {name}", value, *spec[name])
    for name, (_types, default, _range) in spec.items():
        if name not in fields:
            if default is _REQUIRED:
                raise FaultError(f"{where} ({kind}): missing {name}")
            fields[name] = default
    if fields.get("end_s", FOREVER_S) <= fields.get("start_s", 0.0):
        raise FaultError(f"{where} ({kind}) end_s: expected after start_s ({fields['start_s']}), got {fields['end_s']}")
    if kind == "heap" and not re.fullmatch(r"[1-9][0-9]*[KkMm]?", fields["size"]):
        raise FaultError(f"{where} (heap) size: expected bytes like 64K or 1M, got {fields['size']!r}")
    return Fault(i, kind, fields)


def _check_field(where: str, value, types, _default, allowed):
    types = types if isinstance(types, tuple) else (types,)
    if isinstance(value, bool) or not isinstance(value, types):
        names = " or ".join("a number" if t is float else _TYPE_NAMES.get(t, t.__name__) for t in types)
        raise FaultError(f"{where}: expected {names}, got {value!r}")
    if isinstance(allowed, tuple) and isinstance(allowed[0], str):
        if value not in allowed:
            raise FaultError(f"{where}: expected one of {', '.join(allowed)}, got {value!r}")
    elif allowed is not None and not allowed[0] <= value <= allowed[1]:
        raise FaultError(f"{where}: expected {allowed[0]:g} to {allowed[1]:g}, got {value!r}")
    return float(value) if types == _NUM else value


def check_against(faults, plant) -> None:
    """The schedule fits this plant: its signals exist and are of a kind the fault acts
    on; wheel and tether faults need a two-wheel robot plant."""
    for fault in faults:
        where = f"faults[{fault.index}] ({fault.kind})"
        if fault.kind in SIGNAL_KINDS:
            kind = plant.outputs.get(fault.signal)
            if kind is None:
                raise FaultError(
                    f"{where} signal: the plant has no output {fault.signal!r} ({', '.join(plant.outputs)})"
                )
            if kind not in SIGNAL_TYPES[fault.kind]:
                raise FaultError(
                    f"{where} signal: {fault.signal} is a {kind} signal; {fault.kind} acts on "
                    f"{' or '.join(SIGNAL_TYPES[fault.kind])} signals"
                )
        elif fault.kind in PART_KINDS:
            drive = getattr(plant, "drive", None)
            if not hasattr(drive, "motors") or not hasattr(plant, "parts"):
                raise FaultError(f"{where}: needs a two-wheel robot plant, got {type(plant).__name__}")


def harness_faults(faults) -> tuple[Fault, ...]:
    """The faults the harness applies (link, brown-out, heap), not the plant."""
    return tuple(f for f in faults if f.kind in HARNESS_KINDS)


def fault_rng(seed: int, fault: Fault) -> np.random.Generator:
    """The fault's own random stream: from the run's seed and its place in the schedule."""
    return np.random.default_rng([int(seed) & 0xFFFFFFFF, 0xFA17, fault.index])


def with_faults(plant: Plant, faults) -> Plant:
    """``plant``, or a :class:`FaultyPlant` around it if there is a schedule (it keeps the
    whole schedule for the trace header, and applies the faults that act on a plant)."""
    if not faults:
        return plant
    check_against(faults, plant)
    return FaultyPlant(plant, faults)


# -- the plant's outputs ---------------------------------------------------------------

_GLITCHES = ("bounce", "extra_edges")
_SET, _RESTORE, _INVERT = 0, 1, 2  # queued level events: a value, the true level, its opposite


class FaultyPlant(Plant):
    """A plant with a fault schedule: the inner plant's output changes pass through the
    signal faults (held, replaced, dropped, or followed by glitches queued for later) and
    the part faults ride inside the inner plant. The rest of the plant contract is the
    inner plant's (its capabilities too); ``unwrapped`` is the inner plant, and
    ``fault_schedule`` the whole schedule (for the trace header). Other attributes read
    through to the inner plant (tests look at its ground truth so)."""

    WRAPS = True

    def __init__(self, inner: Plant, schedule):
        self.__dict__["inner"] = inner  # (before anything: __getattr__ reads it)
        self.schedule = tuple(schedule)
        self.faults = tuple(f for f in schedule if f.kind not in HARNESS_KINDS)
        self.signal_faults: dict[str, list] = {}
        for f in self.faults:
            if f.kind in SIGNAL_KINDS:
                self.signal_faults.setdefault(f.signal, []).append(f)
        self.fan = 1 + max(
            [2 * f.pairs if f.kind == "bounce" else 2 for f in self.faults if f.kind in _GLITCHES] or [0]
        )
        """Changes an inner change may become (itself and its glitches): the inner plant's
        change limit is divided by it, so a batch stays within its limit."""
        self.inputs = inner.inputs
        self.outputs = inner.outputs
        self.zero_delay = inner.zero_delay
        self.reset(0)

    def __getattr__(self, name):
        return getattr(self.__dict__["inner"], name)

    @property
    def unwrapped(self) -> Plant:
        return self.inner.unwrapped

    @property
    def fault_schedule(self) -> tuple:
        return self.schedule

    def close(self) -> None:
        self.inner.close()

    def reset(self, seed: int) -> None:
        self.inner.reset(seed)
        self.rngs = {f.index: fault_rng(seed, f) for f in self.faults}
        self.queue: list[tuple] = []  # (t_us, n, signal, action, value)
        self.n_queued = 0
        self.skip_next: dict[str, bool] = {}
        self.counts = {f.index: 0 for f in self.faults}
        levels = [n for n in self.signal_faults if self.outputs[n] == "level"]
        self.level = {n: self.inner.output(n) for n in levels}  # what the firmware was last told
        self.true = dict(self.level)  # the inner plant's level, as of the last change passed
        for name in levels:
            for f in self.signal_faults[name]:
                if f.kind == "stuck":
                    self._push(round(f.start_s * 1e6), name, _SET, f.value)
                if f.kind in ("stuck", "dropout") and f.end_s < FOREVER_S:
                    self._push(round(f.end_s * 1e6), name, _RESTORE, None)
        parts = [_PART_MAKERS[f.kind](f, self.rngs[f.index]) for f in self.faults if f.kind in PART_KINDS]
        if parts:
            self.inner.parts.extend(parts)
            for part in parts:
                part.start(0, self.inner)
            self.inner._reschedule()

    @property
    def t_us(self) -> int:
        return self.inner.t_us

    def set_input(self, name: str, value) -> None:
        self.inner.set_input(name, value)

    def set_pwm(self, name: str, freq, duty) -> None:
        self.inner.set_pwm(name, freq, duty)

    def send_bytes(self, name: str, data: bytes, baud) -> None:
        self.inner.send_bytes(name, data, baud)

    def next_change_us(self) -> int:
        nxt = self.inner.next_change_us()
        return min(nxt, self.queue[0][0]) if self.queue else nxt

    def advance_to(self, t_us: int, limit: int = 0) -> list[Change]:
        out: list = []
        inner = self.inner
        while True:
            step = min(t_us, self.queue[0][0]) if self.queue else t_us
            room = max(1, (limit - len(out)) // self.fan) if limit else 0
            for change in inner.advance_to(step, room):
                self._due_before(change[0], out)  # (a glitch queued by an earlier edge)
                self._pass(change, out)
            self._due_before(inner.t_us + 1, out)
            if inner.t_us >= t_us or (limit and len(out) >= limit):
                return out

    def _due_before(self, t_us: int, out: list) -> None:
        queue = self.queue
        while queue and queue[0][0] < t_us:
            self._due(heapq.heappop(queue), out)

    def _push(self, t_us: int, name: str, action: int, value) -> None:
        self.n_queued += 1
        heapq.heappush(self.queue, (t_us, self.n_queued, name, action, value))

    def _due(self, item, out: list) -> None:
        t, _n, name, action, value = item
        true = self.true[name]
        if action == _RESTORE:
            if any(f.kind in ("stuck", "dropout") and f.active(t) for f in self.signal_faults[name]):
                return  # another window holds it still
            value = true
        elif action == _INVERT:
            value = 1 - int(true)
        self._emit_level(t, name, value, out)

    def _emit_level(self, t: int, name: str, value, out: list) -> None:
        if self.level.get(name) != value:
            self.level[name] = value
            out.append(Change(t, name, value))

    def _pass(self, change, out: list) -> None:
        """One change of the inner plant, through the faults on its signal."""
        t, name, value = change
        faults = self.signal_faults.get(name)
        if not faults:
            out.append(change)
            return
        if self.outputs[name] == "level":
            self._pass_level(t, name, value, faults, out)
            return
        for f in faults:
            if not f.active(t):
                continue
            self.counts[f.index] += 1
            if f.kind == "dropout":
                return
            value = _SAMPLE_FAULTS[f.kind](f, value, self.rngs[f.index])
        out.append(Change(t, name, value))

    def _pass_level(self, t: int, name: str, value, faults, out: list) -> None:
        self.true[name] = value
        for f in faults:
            if not f.active(t):
                continue
            if f.kind in ("dropout", "stuck"):
                self.counts[f.index] += 1
                return  # held (the window's end tells the true level)
            if f.kind == "missed_edges" and (self.skip_next.pop(name, False) or self._lose(f, name)):
                self.counts[f.index] += 1
                return
        self._emit_level(t, name, value, out)
        for f in faults:
            if f.active(t) and f.kind in _GLITCHES:
                self._glitches(t, name, f)

    def _lose(self, f: Fault, name: str) -> bool:
        """Lose this edge (and the next, which ends the pulse) with chance ``rate``."""
        if self.rngs[f.index].random() < f.rate:
            self.skip_next[name] = True
            return True
        return False

    def _glitches(self, t: int, name: str, f: Fault) -> None:
        rng = self.rngs[f.index]
        if f.kind == "bounce":
            window = max(2, round(f.bounce_ms * 1000))
            pairs = int(rng.integers(1, f.pairs + 1))
            times = np.sort(rng.choice(np.arange(1, window + 1), size=min(2 * pairs, window), replace=False))
        else:
            if rng.random() >= f.rate:
                return
            start = t + 1 + int(rng.integers(0, f.spread_us))
            times = np.array([start - t, start - t + f.width_us])
        self.counts[f.index] += 1
        for k, dt in enumerate(times.tolist()):
            self._push(t + int(dt), name, _INVERT if k % 2 == 0 else _RESTORE, None)

    def output(self, name: str) -> object:
        if name in self.level:
            return self.level[name]
        return self.inner.output(name)

    def truth(self) -> dict:
        truth = self.inner.truth()
        truth["fault_events"] = {f.label(): self.counts[f.index] for f in self.faults}
        return truth

    def sample_period_us(self, signal: str) -> int | None:
        return self.inner.sample_period_us(signal)

    def snapshot(self):
        mine = (
            list(self.queue),
            self.n_queued,
            dict(self.skip_next),
            dict(self.counts),
            dict(self.level),
            dict(self.true),
        )
        gens = {i: g.bit_generator.state for i, g in self.rngs.items()}
        return self.inner.snapshot(), mine, gens

    def restore(self, snap) -> None:
        inner, mine, gens = snap
        self.inner.restore(inner)
        queue, self.n_queued, skip, counts, level, true = mine
        self.queue, self.skip_next, self.counts = list(queue), dict(skip), dict(counts)
        self.level, self.true = dict(level), dict(true)
        for i, state in gens.items():
            self.rngs[i].bit_generator.state = state


def _forwarded(name: str):
    def forward(self, *args, **kwargs):
        return getattr(self.inner, name)(*args, **kwargs)

    forward.__name__ = name
    forward.__doc__ = f"The inner plant's ``{name}``."
    return forward


for _name in ("capabilities", "world", "start_pose", "catalogue_parts", "summary", "rng"):
    setattr(
        FaultyPlant, _name, property(lambda self, n=_name: getattr(self.inner, n), doc=f"The inner plant's {_name}.")
    )
for _name in (
    "describe", "driven_inputs", "bus_devices", "bus_names", "chip_selects", "tied_chip_selects", "bus_notes",
    "bus_device", "coverage_grid", "footprint", "displays", "bus_transfer", "bitstream", "pose_at", "set_control",
    "wired_signals",
):  # fmt: skip
    setattr(FaultyPlant, _name, _forwarded(_name))


def _stuck(f, value, rng):
    return f.value


def _wrong(f, value, rng):
    return min(65535, max(0, round(value * f.scale + f.offset)))


def _noise(f, value, rng):
    return min(65535, max(0, round(value + rng.normal(0.0, f.sd))))


_SAMPLE_FAULTS = {"stuck": _stuck, "wrong": _wrong, "noise": _noise}


# -- parts inside a robot plant -----------------------------------------------------------


class WheelFault(Part):
    """A wheel jammed (``stuck_wheel``) or slipping (``wheel_slip``) in a window: its
    motor's gain is scaled by ``factor`` (the share of the turn the ground moves; 0 when
    jammed); a slipping wheel's encoder still counts the whole turn."""

    def __init__(self, fault: Fault, rng=None):
        self.wheel = 0 if fault.wheel == "left" else 1
        self.factor = 0.0 if fault.kind == "stuck_wheel" else 1.0 - fault.slip
        self.start_us = round(fault.start_s * 1e6)
        self.end_us = min(NEVER_US - 1, round(fault.end_s * 1e6))
        self.next_us = self.start_us
        self.gain = None  # the motor's own gain, while the fault holds
        self.windows = 0

    def fire(self, t_us: int, plant, out: list) -> None:
        motor = plant.drive.motors[self.wheel]
        if self.gain is None:
            self.gain, motor.gain = motor.gain, motor.gain * self.factor
            self.next_us = self.end_us
            self.windows += 1
        else:
            motor.gain, self.gain = self.gain, None
            self.next_us = NEVER_US
        if plant.drive.settle(t_us, plant):
            plant._motion_changed(t_us)

    def on_motion_change(self, t_us: int, plant) -> None:
        if self.gain is not None and self.factor > 0.0:  # the encoder sees the wheel, not the ground
            rates = plant.drive.encoder_rad_s()
            for enc in plant.encoders:
                if enc.wheel == self.wheel:
                    enc.set_speed(t_us, rates[self.wheel] / self.factor)


class ScheduledSnag(TetherSnag):
    """The tether snag of :mod:`sim_plant.physics.tether` as a scheduled fault: chance ``rate`` per
    spin, drawn from the fault's own stream, only inside the fault's window."""

    def __init__(self, fault: Fault, rng):
        super().__init__(p_snag=fault.rate, pull_m=fault.pull_m, twist_deg=fault.twist_deg, delay_ms=fault.delay_ms)
        self.fault = fault
        self.rng = rng

    def start(self, t_us: int, plant) -> None:
        """(The plant's own snag draws its chances from the plant's stream at reset; this
        one draws from the fault's stream as spins come, and leaves the plant's alone.)"""

    def on_motion_change(self, t_us: int, plant) -> None:
        wl, wr = plant.drive.wheel_rad_s
        spinning = wl * wr < 0.0
        if spinning and not self.spinning and self.fault.active(t_us):
            self.spins += 1
            u, a, b, s = self.rng.random(4).tolist()
            if u < self.p_snag:
                self.pending = (0.5 + 0.5 * a, 0.5 + 0.5 * b, 1.0 if s < 0.5 else -1.0)
                self.next_us = t_us + self.delay_us
        self.spinning = spinning

    def truth(self, t_us: int, plant) -> dict:
        return {"fault_snags": len(self.events), "fault_spins": self.spins}


_PART_MAKERS = {"wheel_slip": WheelFault, "stuck_wheel": WheelFault, "tether_snag": ScheduledSnag}

__all__ = ["KINDS", "Fault", "FaultError", "FaultyPlant", "check_against", "parse_faults", "with_faults"]
