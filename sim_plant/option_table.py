"""The kinds of bounds an option can have, as data: a catalogue part or body declares each
of its options with one of these specs (``sim_plant/catalogue/base.py``, ``Opt``), and a
rig file's ``[plant]`` and ``[[plant.parts]]`` tables, every ``[worlds.*]`` and ``mpy-fil
run --param`` are checked against those declarations (``docs/rig-file.md``, "Bounds").

``spec.problem(value)`` returns None for a value in bounds, else the complaint
(``expected a number of metres from 0.1 to 100, got inf``). The named specs below
(``POSE``, ``BOX``, ``TIME``) are shared by parts whose options mean the same.
"""

import math
import re
from dataclasses import dataclass

SAFE_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.+-]{0,63}")
MAX_ITEMS = 10_000  # rows in a list option (tape points, obstacles)
MAX_TEXT = 200


@dataclass(frozen=True)
class Num:
    """A finite number (``whole``: an integer) from ``lo`` to ``hi``; ``lo`` itself is
    excluded when ``above``; ``none``: None too (the plant's own default)."""

    what: str
    lo: float
    hi: float
    whole: bool = False
    above: bool = False
    none: bool = False

    def problem(self, value):
        if value is None and self.none:
            return None
        if (
            isinstance(value, bool)
            or not isinstance(value, (int, float))
            or (self.whole and not isinstance(value, int))
        ):
            return f"expected {self.text()}, got {value!r}"
        if not math.isfinite(value) or value < self.lo or value > self.hi or (self.above and value == self.lo):
            return f"expected {self.text()}, got {value!r}"
        return None

    def text(self) -> str:
        kind = ("a whole number" if self.whole else "a number") + (f" of {self.what}" if self.what else "")
        if self.above:
            return f"{kind} more than {self.lo:g}, at most {self.hi:g}"
        return f"{kind} from {self.lo:g} to {self.hi:g}"


@dataclass(frozen=True)
class Flag:
    """true or false (not a number)."""

    def problem(self, value):
        return None if isinstance(value, bool) else f"expected true/false, got {value!r}"


@dataclass(frozen=True)
class OneOf:
    """One of a few values (``-1`` or ``1``)."""

    values: tuple

    def problem(self, value):
        ok = not isinstance(value, bool) and value in self.values
        return None if ok else f"expected one of {', '.join(map(str, self.values))}, got {value!r}"


@dataclass(frozen=True)
class Name:
    """A name: letters, digits, ``_ . + -``, at most 64 characters (no path, no control
    characters); the plant checks which names it knows."""

    def problem(self, value):
        if isinstance(value, str) and SAFE_NAME.fullmatch(value):
            return None
        return f"expected a name of letters, digits, '_', '.', '+' or '-' (at most 64), got {_short(value)}"


@dataclass(frozen=True)
class FileName:
    """A file's path, relative to the rig file's folder (``course.png``, ``floors/lap.png``):
    text of at most 200 characters, no control characters. The plant resolves it when the
    rig file is read (:func:`sim_plant.catalogue.assembly.assemble`) and says whether the
    file is there and readable when it builds what uses it."""

    what: str = "a file's path, relative to the rig file"

    def problem(self, value):
        if isinstance(value, str) and 0 < len(value) <= MAX_TEXT and value.isprintable():
            return None
        return f"expected {self.what} (text, at most {MAX_TEXT} characters), got {_short(value)}"


@dataclass(frozen=True)
class Row:
    """A fixed-length list: one spec per place (``[cx, cy, w, h]``)."""

    fields: tuple
    what: str

    def problem(self, value):
        if not isinstance(value, (list, tuple)) or len(value) != len(self.fields):
            return f"expected {self.what}, got {_short(value)}"
        for i, (spec, item) in enumerate(zip(self.fields, value)):
            problem = spec.problem(item)
            if problem:
                return f"{self.what}, item {i}: {problem}"
        return None


@dataclass(frozen=True)
class Rows:
    """A list of ``least`` to ``most`` items, each of ``item``."""

    item: object
    most: int = MAX_ITEMS
    least: int = 0

    def problem(self, value):
        if not isinstance(value, (list, tuple)) or not self.least <= len(value) <= self.most:
            return f"expected a list of {self.least} to {self.most} items, got {_short(value)}"
        for i, item in enumerate(value):
            problem = self.item.problem(item)
            if problem:
                return f"[{i}]: {problem}"
        return None


@dataclass(frozen=True)
class Table:
    """Options passed on to a part (``sonar_options``): at most 32 names, each a finite
    number within +-1e6, true/false, a name, or a list of those; None: none."""

    def problem(self, value):
        if value is None:
            return None
        if not isinstance(value, dict) or len(value) > 32:
            return f"expected a table of at most 32 options, got {_short(value)}"
        for key, item in value.items():
            problem = Name().problem(key) or _scalar_problem(item, depth=0)
            if problem:
                return f"{key}: {problem}"
        return None


def _scalar_problem(value, depth: int):
    if isinstance(value, (list, tuple)) and depth == 0 and len(value) <= 64:
        return next((p for p in (_scalar_problem(v, 1) for v in value) if p), None)
    if isinstance(value, (bool, str)):
        return Flag().problem(value) if isinstance(value, bool) else Name().problem(value)
    return Num("any unit", -1e6, 1e6).problem(value)


def _short(value) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def length(lo, hi, **kw):
    return Num("metres", lo, hi, **kw)


ROOM_SIDE = length(0.1, 100)
"""A room's width or height (the differential's and the desk's room)."""


MAX_T_S = 10 * 24 * 3600  # the longest run (host.rig.config.arguments.MAX_RUN_S)
PLACE = length(-1000, 1000)  # a coordinate
HEADING = Num("radians", -10, 10)
TIME = Num("seconds", 0, MAX_T_S)
POSE = Row((PLACE, PLACE, HEADING), "[x_m, y_m, heading_rad]")
POINT = Row((PLACE, PLACE), "[x_m, y_m]")
BOX = Row((PLACE, PLACE, length(0, 100, above=True), length(0, 100, above=True)), "[cx_m, cy_m, w_m, h_m]")
GAIN = Num("gain", 0, 10)
FRACTION = Num("fraction", 0, 1)
