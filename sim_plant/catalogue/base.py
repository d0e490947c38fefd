"""What a catalogue entry declares, as data: its options (name with the unit in it,
spec from :mod:`sim_plant.option_table`, default, doc), the signals it adds, its ground
truth keys and its views (what a report draws for it).

A **part** (:class:`PartType`) is one class in one module of :mod:`sim_plant.catalogue`;
built with a name, a mount and its options, it adds engine pieces to a plant under
construction (:class:`Build`). A **body** (:class:`BodyType`) owns the pose, the drive
and the contacts. Signals are ``<name>.<signal>``; truth keys ``<name>_<key>`` mostly.
"""

import math
from dataclasses import dataclass, field

from sim_plant.names import unknown
from sim_plant.option_table import Flag, Name, Num, OneOf, Row, Rows

MOUNT_KEYS = ("x_m", "y_m", "heading_deg")
MOUNT_SPEC = {
    "x_m": Num("metres", -10, 10),
    "y_m": Num("metres", -10, 10),
    "heading_deg": Num("degrees", -360, 360),
}


class PartsError(ValueError):
    """A plant's body or parts that cannot be built: the message names the table and
    the field (``[[plant.parts]] #2 (sonar_rear) period_us: expected ...``)."""


@dataclass(frozen=True)
class Opt:
    """One option: ``name`` (unit in it), ``spec`` (bounds), ``default`` (None with a
    ``spec`` that allows it: not set), ``doc``."""

    name: str
    spec: object
    default: object
    doc: str


@dataclass(frozen=True)
class Sig:
    """A signal ``<name>.<suffix>``: ``direction`` ``in`` (the firmware drives it),
    ``out`` (the firmware reads it) or ``io`` (both, in turn: a line the firmware drives
    and lets go, which the part drives while it is let go; an input and an output of the
    plant, the input ``-1`` while let go: docs/wiring.md), ``kind`` (level, u16, duty, pwm,
    bytes); present only when the options match ``when`` (option -> the values it is
    present for)."""

    suffix: str
    direction: str
    kind: str
    doc: str
    when: tuple = ()

    def present(self, options: dict) -> bool:
        return all(options.get(opt) in values for opt, values in self.when)

    def condition(self) -> str:
        return "; ".join(f"{opt} = {' or '.join(map(str, values))}" for opt, values in self.when)


@dataclass(frozen=True)
class View:
    """What a report draws for a part: a ``plot`` kind (``range``, ``command``,
    ``count``, ``contacts``, ``level``, ``voltage``, ``angle``, ``rate``, ``heading``,
    ``coverage``) of its ``signals``
    (suffixes) against its ``truth`` (keys, ``{name}`` the part's)."""

    plot: str
    doc: str
    signals: tuple = ()
    truth: tuple = ()


@dataclass
class Build:
    """A plant being built, what parts add to: the body's options (``body``), engine
    parts, encoders, bumpers, motors (``motors[side] = (bridge, DcMotor)``), servos
    (``servos[name]``: what a part mounted on one turns with), the motors' shared
    ``standby`` pin and track stop inputs (``tracks[side] = signal``), and the
    plant's generator (``rng``)."""

    body: dict
    parts: list = field(default_factory=list)
    encoders: list = field(default_factory=list)
    bumpers: list = field(default_factory=list)
    motors: dict = field(default_factory=dict)
    servos: dict = field(default_factory=dict)
    standby: str | None = None
    tracks: dict = field(default_factory=dict)
    rng: object = None
    """The plant's generator, freshly seeded: for what a part draws once at build time."""
    controls: object = None
    """The plant's control timeline (:mod:`sim_plant.controls`): what a part with
    ``CONTROLS`` reads its controls' values from."""


class Declared:
    """Shared by parts and bodies: ``kind``, ``doc`` and ``OPTIONS``."""

    kind: str = ""
    doc: str = ""
    OPTIONS: tuple = ()
    FIXED_STATE = True  # (a declaration, as built: a plant's snapshot leaves it out)

    @classmethod
    def defaults(cls) -> dict:
        return {o.name: o.default for o in cls.OPTIONS}

    @classmethod
    def checked(cls, given: dict, where: str, skip=()) -> dict:
        """``given`` over the defaults; an unknown option or a value out of bounds is a
        :class:`PartsError` naming ``where`` and the option."""
        known = {o.name: o for o in cls.OPTIONS}
        for name, value in given.items():
            if name in skip:
                continue
            if name not in known:
                options = unknown(name, known, what="options")
                raise PartsError(f"{where} {name}: the {cls.kind} has no such option {options}")
            opt = known[name]
            if value is None and opt.default is None:
                continue
            problem = opt.spec.problem(value)
            if problem:
                raise PartsError(f"{where} {name}: {problem}")
        return {**cls.defaults(), **{k: v for k, v in given.items() if k not in skip}}


class PartType(Declared):
    """A part: built with its ``name``, ``mount`` (x_m, y_m, heading_deg on the body)
    and checked ``options``. ``SIGNALS``, ``TRUTH`` (keys, ``{name}`` the part's) and ``VIEWS`` are
    declarations; :meth:`add` puts its engine pieces into a :class:`Build`.
    ``needs_body``: it senses or acts on a body that moves (not on a bench);
    ``zero_delay``: an input of it may change an output at the same instant (a wire);
    ``reads_empty``: its outputs are bytes as events (a UART configured on one reads nothing);
    ``timed``: its inputs take a PIO's edges each at its own instant (a clocked serial chip:
    ``sim_plant.plant.LevelAt``), not a burst's last level;
    ``on_bus``: a chip on a bus (options ``bus``, ``address``, ``spi``: ``sim_plant.buses``).
    A chip (a part with a ``bus`` option, or a strip of LEDs) declares what its model does,
    ``MODELLED_FEATURES``, and what of the datasheet's chip it does not, ``NOT_MODELLED``, a
    line each: ``docs/parts.md`` shows them (a register chip's registers from its ``CHIP``'s
    ``MODELLED``), and ``sim_plant/tests/test_parts_modelled.py`` holds every chip to it."""

    SIGNALS: tuple = ()
    TRUTH: tuple = ()
    VIEWS: tuple = ()
    CONTROLS: tuple = ()  # sim_plant.controls.Control: what a scenario's set-control sets
    MODELLED_FEATURES: tuple = ()  # a chip's: what its model does (docs/parts.md)
    NOT_MODELLED: tuple = ()  # a chip's: what of the datasheet's chip its model does not do
    needs_body = False
    zero_delay = False
    reads_empty = False
    timed = False
    on_bus = False
    rig_file: str | None = None  # the rig file it was read from (set by assemble): a run's messages name it

    def __init__(self, name: str, mount: dict, options: dict):
        self.name = name
        self.mount = tuple(float(mount.get(k, 0.0)) for k in MOUNT_KEYS)
        self.options = options
        self.check()

    def check(self) -> None:
        """Refuse option combinations the bounds alone do not catch (ValueError)."""

    def mount_rad(self) -> tuple[float, float, float]:
        x, y, heading_deg = self.mount
        return x, y, math.radians(heading_deg)

    def signals(self) -> dict[str, tuple[str, str]]:
        """Full signal name -> (direction, kind), for these options."""
        return {f"{self.name}.{s.suffix}": (s.direction, s.kind) for s in self.SIGNALS if s.present(self.options)}

    def add(self, build: Build) -> None:
        raise NotImplementedError

    def control_change(self, control: str, value) -> tuple | None:
        """Check ``value`` for ``control`` (a ControlError names the part's controls); the
        output (signal, level) it sets at once (or a list of them), or None when the part
        reads it on demand."""
        from sim_plant.controls import ControlError

        known = {c.name: c for c in self.CONTROLS}
        if control not in known:
            has = ", ".join(known) if known else "none"
            close = unknown(control, known, what="controls").rpartition(")")[2]
            raise ControlError(f"{self.name} ({self.kind}) has no control {control!r} (controls: {has}){close}")
        problem = known[control].spec.problem(value)
        if problem:
            raise ControlError(f"{self.name} ({self.kind}) {control}: {problem}")
        return None


class BodyType(Declared):
    """A body: owns the pose, the drive and the contacts; ``moves`` is False for a bench."""

    moves = True
    draws_world = False
    """True: :meth:`world_and_pose` takes the plant's generator (a world drawn per seed)."""

    def __init__(self, options: dict):
        self.options = options

    def world_and_pose(self):
        """(the world, the start pose (x_m, y_m, heading_rad)); with ``draws_world``,
        called with the plant's freshly seeded generator."""
        raise NotImplementedError

    def drive(self, build: Build, pose):
        """The drive (an engine Part with a ``body``) from what the parts added."""
        raise NotImplementedError

    def contact_monitor(self, build: Build):
        """The engine part that checks the body against the walls, or None."""
        return None

    def recorders(self, build: Build, world) -> list:
        """Engine parts after the catalogue parts that only watch the body (coverage)."""
        return []

    def react(self, plant, t_us: int) -> bool:
        """The body's own reaction after the parts fired at ``t_us`` (a machine that
        reverses at its bumpers); True if the motion changed."""
        return False


class WorldType(Declared):
    """A world a body moves in (the body's ``world = "<kind>"``, its options in the body's
    ``world_options`` table): :meth:`build` gives the :class:`~sim_plant.world.World` and the
    start pose (x_m, y_m, heading_rad) the body takes unless the rig file sets its own.
    ``draws``: :meth:`build` takes the plant's freshly seeded generator (drawn per seed)."""

    draws = False

    def __init__(self, options: dict):
        self.options = options

    def build(self, rng=None):
        raise NotImplementedError


class ReportView(Declared):
    """A view a rig file names in ``[report] views``: :meth:`panels` gives the report's
    panels of a trace folder (``trace``: its signals, truth and console), drawn with the
    ``kit`` the report passes (``Panel``, ``Line``, ``US_PER_S``, ``rows``, ``console_text``,
    ``firmware_t0_us``: ``host/report/viewkit.py``), so a view imports nothing of the host."""

    def __init__(self, options: dict | None = None):
        self.options = options or {}

    def panels(self, trace, kit) -> list:
        raise NotImplementedError


class Judge(Declared):
    """How a campaign's run passes (``[campaign] judge = "<kind>"``): :meth:`judge` reads the
    finished rig (``rig.console``, ``rig.truth()``, ``rig.plant``, ``rig.t_us``) and gives
    (passed, figures, message); ``FIGURES``: the figures a campaign is ranked by when it names
    none (the first its runs have)."""

    FIGURES: tuple = ("t_end_s",)

    def __init__(self, options: dict | None = None):
        self.options = options or {}

    def judge(self, rig, reached: bool, task: dict):
        raise NotImplementedError


class WorldKind:
    """The ``world`` option: the body's own worlds (the differential's room and furnished
    room) or a world of the catalogue (ours, a user's, or ``"module:Class"``:
    :class:`~sim_plant.catalogue.base.WorldType`)."""

    def __init__(self, own: tuple = ("room", "furnished")):
        self.own = own  # the body's own worlds, made from its options

    @property
    def what(self) -> str:
        kind = "a catalogue world's kind (below; docs/own-parts.md)"
        return f"{', '.join(self.own)}, or {kind}" if self.own else kind

    @property
    def values(self) -> tuple:
        from sim_plant import catalogue

        return (*self.own, *catalogue.worlds())

    def problem(self, value):
        from sim_plant import catalogue

        if isinstance(value, str) and (value in self.own or catalogue.resolve("worlds", value)):
            return None
        return f"expected one of {', '.join(self.values)} or a world's 'module:Class', got {value!r}"[:300]


class WorldOptions:
    """The ``world_options`` table: a catalogue world's options (it checks them itself)."""

    what = "a table of the world's options"

    def problem(self, value):
        return None if isinstance(value, dict) else f"expected a table of the world's options, got {value!r}"[:200]


def catalogue_world(kind: str, options: dict, rng):
    """A catalogue world's (World, start pose), its options checked as a part's are."""
    from sim_plant import catalogue

    cls = catalogue.resolve("worlds", kind)
    world = cls(cls.checked(options, "[plant] world_options"))
    return world.build(rng) if cls.draws else world.build()


def spec_text(spec) -> str:
    """One line for an option's bounds (docs, ``mpy-fil list``)."""
    if isinstance(spec, Num):
        return spec.text() + (" or unset" if spec.none else "")
    if isinstance(spec, OneOf):
        return "one of " + ", ".join(map(str, spec.values))
    if isinstance(spec, Flag):
        return "true/false"
    if isinstance(spec, Name):
        return "a name"
    if isinstance(spec, Row):
        return spec.what
    if isinstance(spec, Rows):
        return f"a list of {spec.least} to {spec.most} of: {spec_text(spec.item)}"
    return getattr(spec, "what", type(spec).__name__)


__all__ = [
    "CS_OPTION",
    "CS_SIGNAL",
    "SCK_SIGNAL",
    "Build",
    "BodyType",
    "Judge",
    "Opt",
    "PartType",
    "PartsError",
    "ReportView",
    "Sig",
    "View",
    "WorldKind",
    "WorldOptions",
    "WorldType",
    "catalogue_world",
    "spec_text",
]


CS_OPTION = Opt(
    "cs",
    OneOf(("pin", "low")),
    "pin",
    'SPI only: "pin": its chip select is the cs input, wired to a pin the firmware drives; '
    '"low": tied to ground (selected for good, no cs input)',
)
CS_SIGNAL = Sig(
    "cs", "in", "level", "the chip select (SPI only: low selects it)", when=(("spi", (True,)), ("cs", ("pin",)))
)
"""A part on either bus (sim_plant/buses.py): its ``cs`` option and its chip-select input (present on SPI
unless the rig ties it low)."""
SCK_SIGNAL = Sig(
    "sck",
    "in",
    "level",
    "the pin of its SPI clock (SPI only): wired, a transfer reaches the chip only while that pin is the SPI's"
    " (rp2: FUNCSEL SPI, by SPI(..., sck=), Pin.ALT alt=1 or mem32), as when parts share MOSI on one"
    " controller with a clock pin each; not wired, every transfer on its bus does",
    when=(("spi", (True,)),),
)
