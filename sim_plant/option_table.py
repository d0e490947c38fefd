"""Every plant option's type, unit and bounds, as data: the one table a rig file's
``[plant.options]`` and ``[worlds.*]`` and ``mpy-fil run --param`` are checked against
(``docs/rig-file.md``). An option means the same in every kind that has it, so the table
is keyed by the option's name; a part that declares its own options later takes its rows.

``check(name, value)`` returns None for a value in bounds, else the complaint (``expected
a length in metres from 0.1 to 100, got inf``); an option not in the table is left to
the plant (and to ``test_every_option_of_every_kind_has_bounds``, which fails).
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


def period(lo_us, hi_us):
    return Num("microseconds", lo_us, hi_us, whole=True)


def count(lo, hi):
    return Num("", lo, hi, whole=True)


MAX_T_S = 10 * 24 * 3600  # the longest run (host.rig.arguments.MAX_RUN_S)
ROOM = length(0.1, 100)  # a room, pool or duct side
PLACE = length(-1000, 1000)  # a coordinate
SIZE = length(0, 100, above=True)  # a box's side
HEADING = Num("radians", -10, 10)
TIME = Num("seconds", 0, MAX_T_S)
POSE = Row((PLACE, PLACE, HEADING), "[x_m, y_m, heading_rad]")
POINT = Row((PLACE, PLACE), "[x_m, y_m]")
BOX = Row((PLACE, PLACE, SIZE, SIZE), "[cx_m, cy_m, w_m, h_m]")
GAIN = Num("gain", 0, 10)
NOISE = length(0, 10)
BOUNCE = period(0, 1_000_000)
SAMPLE = period(100, 1_000_000_000)  # a sensor's sample period: 100 us to 1000 s
FRACTION = Num("fraction", 0, 1)

OPTIONS = {
    # the world and the body
    "world": Name(),
    "room_w_m": ROOM,
    "room_h_m": ROOM,
    "start_pose": Row((PLACE, PLACE, HEADING), "[x_m, y_m, heading_rad]"),
    "obstacles": Rows(BOX, 1000),
    "placements": Rows(Row((TIME, PLACE, PLACE, SIZE, SIZE), "[t_s, cx_m, cy_m, w_m, h_m]"), 1000),
    "route": Rows(POINT, 1000, least=1),
    "body_radius_m": length(0.01, 5),
    "wheel_radius_m": length(0.001, 1),
    "track_m": length(0.01, 10),
    "coverage_cell_m": length(0.02, 10),
    # motors and drive
    "v_max_m_s": Num("metres per second", 0, 20, above=True),
    "motor_rpm": Num("revolutions per minute", 0, 100_000, above=True, none=True),
    "deadband_duty": Num("duty", 0, 0.99),
    "motor_gains": Row((GAIN, GAIN), "[left_gain, right_gain]"),
    "motor_time_constant_ms": Num("milliseconds", 0, 10_000),
    "gear_ratio": Num("motor turns per wheel turn", 0.01, 10_000),
    "bridge": Name(),
    "standby": Flag(),
    "spin_slip": FRACTION,
    "wheel_slip_sd": FRACTION,
    "slip_period_us": SAMPLE,
    # encoders
    "encoder": Name(),
    "lines_per_rev": count(1, 10_000),
    "encoder_polarity": Row((OneOf((-1, 1)), OneOf((-1, 1))), "[left, right] of -1 or 1"),
    "polarity": Row((OneOf((-1, 1)), OneOf((-1, 1))), "[left, right] of -1 or 1"),
    "missed_edge_p": Num("probability", 0, 0.5),
    # rangers and sonars
    "ranger": Name(),
    "ranger_period_us": SAMPLE,
    "hcsr04_trigger_min_us": period(1, 1_000),
    "sonar_period_us": SAMPLE,
    "sonar_phase_us": period(0, 1_000_000_000),
    "sonar_ranging_us": period(1, 1_000_000),
    "sonar_rx": Flag(),
    "adc_bits": count(1, 24),
    "adc_vref_v": Num("volts", 0.1, 50),
    # contacts, buttons, floor, links
    "bumper": Flag(),
    "bumper_bounce_us": BOUNCE,
    "buttons": Rows(Name(), 32),
    "presses": Rows(Row((Name(), TIME, TIME), "[name, t_press_s, t_release_s]"), 1000),
    "button_bounce_us": BOUNCE,
    "program_jumper": Flag(),
    "line_sensors": Rows(Row((length(-10, 10), length(-10, 10)), "[dx_m, dy_m]"), 64),
    "tape": Rows(POINT),
    "tape_width_m": length(0.001, 1),
    "tape_u16": count(0, 65_535),
    "floor_u16": count(0, 65_535),
    "floor_period_us": SAMPLE,
}


def check(name: str, value):
    """None when ``value`` is within ``name``'s bounds (or the table has no ``name``),
    else what was expected and what came."""
    spec = OPTIONS.get(name)
    return None if spec is None else spec.problem(value)


def describe(name: str) -> str:
    """One line of the bounds, for docs and ``mpy-fil list``."""
    spec = OPTIONS[name]
    return spec.text() if isinstance(spec, Num) else type(spec).__name__
