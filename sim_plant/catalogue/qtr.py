"""Part ``qtr``: RC-decay reflectance sensors (Pololu QTR-xRC class, the line and bump
sensors of robot kits such as the 3pi+ 2040), one channel or an array looking at the
floor at offsets from the mount, read by timing a capacitor's discharge.

Each channel is one board pin on the sensor's output node, a capacitor in parallel with
a phototransistor (Pololu's QTR-xRC documentation: "turn on IR LEDs, set the I/O line to
an output and drive it high, allow at least 10 µs for the sensor output to rise, make the
I/O line an input (high impedance), measure the time for the voltage to decay by waiting
for the I/O line to go low"). The line ``<name>.<i>`` is one signal both ways: the board
drives it (an input of the plant: 1 high, 0 low, ``RELEASED`` (-1, or None) when the
board makes the pin an input again, a ``sim_plant.plant.ReleasedAt`` when a PIO state
machine's ``pindirs`` let it go at a later cycle: the discharge starts there) and reads it
(an output: the node's level).

- Driven high, the node reads 1 at once and charges; a drive shorter than ``charge_us``
  charges it in proportion (its discharge then lasts that fraction of the full one).
- Driven low, it reads 0 and holds no charge.
- Let go after a charge, it reads 1 for the discharge time, then 0: ``white_us`` over the
  floor, ``black_us`` over the body's ``tape`` (the floor's dark line, as ``line_sensor``
  sees it) or a world's picture's black (``line_course``), in proportion between over its
  greys and edges, ``unlit_us`` while the emitter is off (ambient light only: longer than any
  driver's timeout, which the driver then reads). The floor under the channel and the
  emitter are taken at the instant it is let go; a change during the discharge does not
  change its length.
- The emitter: ``emitter = "high"`` lights the LEDs while the board drives
  ``<name>.emitter`` high (the 3pi+'s line emitters), ``"low"`` while it drives it low,
  ``"none"``: always lit (no control line).

Not modelled: the exponential shape of the decay (a read of the level is 1 or 0, the
threshold crossing is the instant the time says), ambient light other than ``unlit_us``,
the spot a channel sees (the floor's darkness at one point: on the tape or not, as
``line_sensor``; a picture's darkness between its pixels),
channel-to-channel spread and noise.

A bump sensor (the 3pi+'s two, looking at the inside of its bumper's flaps): with
``flaps_deg``, channel ``i`` looks at a flap over an arc of the body's edge instead of the
floor, ``[centre_deg, half_arc_deg]`` from the heading (positive to the left), and reads
``black_us`` while the flap is pressed (the body touches a wall inside the arc, as a
``bumper`` part's switch closes: ``sim_plant.contacts``) and ``white_us`` while it is not; the ground truth has each
flap's ``<name>.flap<i>_pressed``. Not modelled for flaps: how far a flap is pressed
(pressed or not), its spring's delay."""

import math

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.contacts import Bumper
from sim_plant.floor import DARK, FloorSensors
from sim_plant.option_table import Num, OneOf, Row, Rows, length
from sim_plant.plant import NEVER_US, Change

OFFSET = Row((length(-10, 10), length(-10, 10)), "[dx_m, dy_m]")
ARC = Row((Num("degrees", -180, 180), Num("degrees", 0, 180, above=True)), "[centre_deg, half_arc_deg]")
RELEASED = -1
"""A line's input when the board lets it go (the pin an input again)."""
TIME_US = Num("microseconds", 1, 10_000_000, whole=True)


class RcLines(FloorSensors):
    """The channels' lines and their capacitors, on the floor's tape."""

    FIXED_STATE = (*FloorSensors.FIXED_STATE, "emitter_signal")

    def __init__(self, name: str, offsets, tape, *, width_m, times_us, charge_us, emitter, flaps=()):
        self.flaps = list(flaps)  # (a bump sensor's: the contacts' switches its channels look at)
        super().__init__(offsets, tape, width_m=width_m, tape_u16=1, floor_u16=0, period_us=1)
        self.label = name
        self.names = [f"{name}.{i}" for i in range(len(self.offsets))]
        self.white_us, self.black_us, self.unlit_us = times_us
        self.charge_us = charge_us
        self.emitter = emitter
        self.emitter_signal = f"{name}.emitter" if emitter != "none" else None
        self.inputs = dict.fromkeys(self.names, "level")
        if self.emitter_signal:
            self.inputs[self.emitter_signal] = "level"
        self.outputs = dict.fromkeys(self.names, "level")
        n = len(self.names)
        self.lit = emitter == "none"
        self.levels_now = [0] * n  # each node's level as the board reads it
        self.high_since = [None] * n  # driven high since (None: not driven high)
        self.charge = [0.0] * n  # the fraction of a full charge the node holds
        self.falls_at = [NEVER_US] * n  # when a let-go node's level falls
        self.due = []  # channels whose level changes at the next fire (an instant's drive)
        self.last_us = [None] * n  # each channel's last discharge time
        self.on_tape = [False] * n  # each channel's floor at its last release
        self.next_us = NEVER_US

    def start(self, t_us: int, plant) -> None:
        self.look_at_world(plant)
        self.next_us = NEVER_US

    def initial_outputs(self) -> dict:
        return dict(zip(self.names, self.levels_now))

    def set_input(self, name: str, value, t_us: int, plant) -> bool:
        if name == self.emitter_signal:  # (let go, the control line is no one's: the emitters are off)
            driven = value is not None and value >= 0
            self.lit = driven and bool(value) == (self.emitter == "high")
            return False
        i = self.names.index(name)
        if value is None or value < 0:  # let go: the capacitor discharges from here
            at_us = max(t_us, getattr(value, "at_us", t_us))  # (a PIO's pindirs change: at its cycle)
            held = self.charge[i]
            if self.high_since[i] is not None:
                held = max(held, min(1.0, (at_us - self.high_since[i]) / self.charge_us))
            self.high_since[i] = None
            self.charge[i] = held
            high = dict(self.due).get(i, self.levels_now[i])  # (driven high at this instant: not yet fired)
            if high and held > 0:
                dark = self.darkness(plant, t_us)[i]
                self.on_tape[i] = dark >= DARK
                full = self.unlit_us if not self.lit else self.discharge_us(dark)
                self.last_us[i] = round(full * held)
                self.falls_at[i] = round(at_us + full * held)
            else:
                self.falls_at[i] = t_us  # (nothing held: it reads low at once)
        elif value:
            if self.high_since[i] is None:
                self.high_since[i] = t_us
            self.falls_at[i] = NEVER_US
            self.due.append((i, 1))
        else:
            self.high_since[i] = None
            self.charge[i] = 0.0
            self.falls_at[i] = NEVER_US
            self.due.append((i, 0))
        self._plan(t_us)
        return False

    def darkness(self, plant, t_us: int) -> list:
        """What each channel sees: the floor's darkness, or 1 for a pressed flap."""
        if self.flaps:
            return [1.0 if flap.pressed else 0.0 for flap in self.flaps]
        return self.dark(plant.pose_at(t_us))

    def discharge_us(self, dark: float) -> int:
        """The full discharge time, lit, over a floor this dark (0 white .. 1 black)."""
        if dark <= 0.0 or dark >= 1.0:
            return self.black_us if dark >= 1.0 else self.white_us
        return round(self.white_us + dark * (self.black_us - self.white_us))

    def _plan(self, t_us: int) -> None:
        self.next_us = t_us if self.due else min(self.falls_at)

    def fire(self, t_us: int, plant, out: list) -> None:
        changes = dict(self.due)
        self.due = []
        for i, at in enumerate(self.falls_at):
            if at <= t_us:
                changes[i] = 0
                self.falls_at[i] = NEVER_US
                self.charge[i] = 0.0
        for i, level in sorted(changes.items()):
            if level != self.levels_now[i]:
                self.levels_now[i] = level
                out.append(Change(t_us, self.names[i], level))
        self._plan(t_us)

    def truth(self, t_us: int, plant) -> dict:
        return {
            f"{self.label}_on_tape": [d >= DARK for d in self.darkness(plant, t_us)],
            f"{self.label}_discharge_us": list(self.last_us),
        }


class Qtr(PartType):
    kind = "qtr"
    doc = (
        "RC-decay reflectance sensors (QTR-xRC class, a kit's line or bump sensors): each channel's pin is driven"
        " high, let go, and reads 1 for a discharge time set by the floor under it (white_us, black_us over the"
        " tape or a line_course picture's black, in proportion over its greys) and the emitter (unlit_us while"
        " off). A channel's line is an io signal: the firmware's pin drives it, and lets it go when made an input"
        " again (Pin.IN, or open drain and high), at that instant (docs/wiring.md)."
    )
    OPTIONS = (
        Opt(
            "offsets_m",
            Rows(OFFSET, 31, least=1),
            [[0.0, 0.0]],
            "each channel's place from the mount, along and across its heading (channel 0, 1, ...)",
        ),
        Opt(
            "flaps_deg",
            Rows(ARC, 31),
            [],
            "a bump sensor's: each channel looks at a bumper flap over this arc of the body's edge (0 the front,"
            " positive to the left) and reads black_us while the body touches a wall inside it; empty: the floor",
        ),
        Opt("white_us", TIME_US, 150, "the discharge time over the floor, emitter on (much light back)"),
        Opt("black_us", TIME_US, 800, "the discharge time over the tape, emitter on (little light back)"),
        Opt(
            "unlit_us",
            TIME_US,
            5_000,
            "the discharge time with the emitter off (ambient light only): past a driver's timeout",
        ),
        Opt("charge_us", TIME_US, 10, "a drive high this long charges the capacitor fully (the datasheet's 10 us)"),
        Opt(
            "emitter",
            OneOf(("high", "low", "none")),
            "high",
            "the IR emitters are lit while the board drives <name>.emitter high (high), low (low), or always (none)",
        ),
    )
    SIGNALS = (
        Sig(
            "<i>",
            "io",
            "level",
            "channel i's line, both ways: the board drives it high to charge, lets it go, and reads it fall",
        ),
        Sig("emitter", "in", "level", "the IR emitters' control line", (("emitter", ("high", "low")),)),
    )
    TRUTH = ("{name}_on_tape", "{name}_discharge_us")
    VIEWS = (
        View(
            "level",
            "each channel's line against whether it is over the tape",
            signals=("<i>",),
            truth=("{name}_on_tape",),
        ),
    )
    needs_body = True
    zero_delay = True  # (a drive is on the line at the same instant)

    def check(self) -> None:
        o = self.options
        if o["flaps_deg"] and len(o["flaps_deg"]) != len(o["offsets_m"]):
            raise ValueError(
                f"flaps_deg: expected an arc for each of the {len(o['offsets_m'])} channels (offsets_m), got "
                f"{len(o['flaps_deg'])}"
            )
        if not o["white_us"] < o["black_us"] <= o["unlit_us"]:
            raise ValueError(
                f"white_us < black_us <= unlit_us expected (more light, a faster discharge), got "
                f"{o['white_us']}, {o['black_us']}, {o['unlit_us']}"
            )

    def signals(self) -> dict[str, tuple[str, str]]:
        lines = {f"{self.name}.{i}": ("io", "level") for i in range(len(self.options["offsets_m"]))}
        if self.options["emitter"] != "none":
            lines[f"{self.name}.emitter"] = ("in", "level")
        return lines

    def add(self, build: Build) -> None:
        o = self.options
        mx, my, heading = self.mount_rad()
        c, s = math.cos(heading), math.sin(heading)
        offsets = [(mx + dx * c - dy * s, my + dx * s + dy * c) for dx, dy in o["offsets_m"]]
        flaps = [
            Bumper(f"{self.name}.flap{i}", center_deg=centre, half_arc_deg=half, active_low=False, wired=False)
            for i, (centre, half) in enumerate(o["flaps_deg"])
        ]
        build.bumpers.extend(flaps)
        build.parts.append(
            RcLines(
                self.name,
                offsets,
                build.body.get("tape", []),
                width_m=build.body.get("tape_width_m", 0.019),
                times_us=(o["white_us"], o["black_us"], o["unlit_us"]),
                charge_us=o["charge_us"],
                emitter=o["emitter"],
                flaps=flaps,
            )
        )
