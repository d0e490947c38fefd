"""A part's controls: what a person (or a scenario's ``set-control`` step) sets on a
part while the rig runs, at a virtual instant: a button's ``pressed``, an HC-SR04's
``distance``, an MPU6050's ``accelX``... A part declares its controls
(``PartType.CONTROLS``); the plant keeps every value set in one :class:`ControlTimeline`.

The timeline is an engine part: a control that sets an output level (a button) fires
that level's change at its instant, as a scripted press does; a sensor read on demand
(a ping, a register read) asks :meth:`ControlTimeline.value_at` the value in force at
the instant it measures. Values set are never rewound with the plant's speculative
batches (the timeline's entries are not part of a snapshot): a rewind to before an
instant that was set replays it when the plant comes past it again.
"""

from dataclasses import dataclass

from sim_plant.engine import Part
from sim_plant.plant import NEVER_US, Change


@dataclass(frozen=True)
class Control:
    """One control of a part: ``name`` (as Wokwi names it), ``spec`` (bounds, from
    :mod:`sim_plant.option_table`), ``doc`` (with its unit)."""

    name: str
    spec: object
    doc: str


class ControlError(ValueError):
    """A control that does not exist or a value out of its bounds: the message names the
    part and its controls."""


class ControlTimeline(Part):
    """Every control value set, in the order of its instant: ``entries`` of
    ``(t_us, part, control, value, changes)`` (``changes``: the (signal, level) outputs it
    sets at that instant; empty: read on demand)."""

    FIXED_STATE = ("entries", "inputs", "outputs")  # (never rewound: see the module doc)

    def __init__(self):
        self.entries: list[tuple] = []
        self.i = 0  # the next entry to fire (rewound with the plant)

    @property
    def next_us(self) -> int:
        entries, i = self.entries, self.i
        n = len(entries)
        while i < n and not entries[i][4]:
            i += 1
        return entries[i][0] if i < n else NEVER_US

    def set(self, t_us: int, part: str, control: str, value, change=None) -> None:
        """``part``'s ``control`` is ``value`` from ``t_us`` on; ``change``: the output
        (signal, level) it sets at that instant, a list of them, or None."""
        if self.entries and t_us < self.entries[-1][0]:
            raise ControlError(
                f"{part}.{control}: set at t={t_us} us, before the last control set ({self.entries[-1][0]} us)"
            )
        changes = () if change is None else (change,) if isinstance(change[0], str) else tuple(change)
        self.entries.append((t_us, part, control, value, changes))

    def value_at(self, part: str, control: str, t_us: int, default=None):
        """The value of ``part``'s ``control`` in force at ``t_us`` (``default``: never set)."""
        for entry in reversed(self.entries):
            if entry[0] <= t_us and entry[1] == part and entry[2] == control:
                return entry[3]
        return default

    def last_set(self, part: str, control: str, t_us: int) -> tuple | None:
        """``(t_set_us, value)`` of the last time ``part``'s ``control`` was set at or before
        ``t_us`` (None: never): for a part whose own state starts again from a set value
        (a battery drains on from the voltage set)."""
        for entry in reversed(self.entries):
            if entry[0] <= t_us and entry[1] == part and entry[2] == control:
                return entry[0], entry[3]
        return None

    def fire(self, t_us: int, plant, out: list) -> None:
        entries = self.entries
        while self.i < len(entries) and entries[self.i][0] <= t_us:
            for signal, level in entries[self.i][4]:
                out.append(Change(t_us, signal, level))
            self.i += 1
