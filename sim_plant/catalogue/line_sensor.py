"""Part ``line_sensor``: reflectance sensors looking at the floor (TCRT5000, QTR), one or
an array at offsets from the mount, analog (an ADC reading, high over the dark tape) or
digital (a comparator's output, 1 over the tape). The floor is the body's ``tape`` and
the world's picture (``line_course``): an analog reading goes from ``floor_u16`` over
white to ``tape_u16`` over black in proportion to the darkness under the sensor, a
digital one is 1 where the floor is more than half dark (:class:`sim_plant.floor.FloorSensors`)."""

import math

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.floor import DARK, FloorSensors
from sim_plant.option_table import Num, OneOf, Row, Rows, length

OFFSET = Row((length(-10, 10), length(-10, 10)), "[dx_m, dy_m]")


class _Named(FloorSensors):
    """The sensors, their signals ``<name>.0``, ``<name>.1`` ... of ``kind``."""

    def __init__(self, name: str, kind: str, offsets, tape, **options):
        super().__init__(offsets, tape, **options)
        self.names = [f"{name}.{i}" for i in range(len(self.offsets))]
        self.outputs = dict.fromkeys(self.names, kind)
        self.label = name

    def truth(self, t_us: int, plant) -> dict:
        return {f"{self.label}_on_tape": [d >= DARK for d in self.darks]}


class LineSensor(PartType):
    kind = "line_sensor"
    doc = (
        "Floor reflectance sensors (one or an array), analog or digital, seeing the body's tape and the world's"
        " picture of the floor (line_course): analog, from floor_u16 (white) to tape_u16 (black) in proportion"
        " to the darkness; digital, 1 where it is more than half dark."
    )
    OPTIONS = (
        Opt("output", OneOf(("analog", "digital")), "analog", "an ADC reading or a comparator's level"),
        Opt(
            "offsets_m",
            Rows(OFFSET, 64, least=1),
            [[0.0, 0.0]],
            "each sensor's place from the mount, along and across its heading",
        ),
        Opt("tape_u16", Num("", 0, 65_535, whole=True), 58_000, "the analog reading over the tape (black)"),
        Opt("floor_u16", Num("", 0, 65_535, whole=True), 6_000, "the analog reading over the floor (white)"),
        Opt("period_us", Num("microseconds", 100, 1_000_000_000, whole=True), 1_000, "the floor is looked at every"),
    )
    SIGNALS = (
        Sig("<i>", "out", "u16", "sensor i's reading (0, 1, ... in offsets_m's order)", (("output", ("analog",)),)),
        Sig("<i>", "out", "level", "sensor i's level, 1 over the tape", (("output", ("digital",)),)),
    )
    TRUTH = ("{name}_on_tape",)
    VIEWS = (
        View(
            "level",
            "each sensor's reading against whether it is over the tape",
            signals=("<i>",),
            truth=("{name}_on_tape",),
        ),
    )
    needs_body = True

    def signals(self) -> dict[str, tuple[str, str]]:
        kind = "u16" if self.options["output"] == "analog" else "level"
        return {f"{self.name}.{i}": ("out", kind) for i in range(len(self.options["offsets_m"]))}

    def add(self, build: Build) -> None:
        o = self.options
        mx, my, heading = self.mount_rad()
        c, s = math.cos(heading), math.sin(heading)
        offsets = [(mx + dx * c - dy * s, my + dx * s + dy * c) for dx, dy in o["offsets_m"]]
        analog = o["output"] == "analog"
        build.parts.append(
            _Named(
                self.name,
                "u16" if analog else "level",
                offsets,
                build.body.get("tape", []),
                width_m=build.body.get("tape_width_m", 0.019),
                tape_u16=o["tape_u16"] if analog else 1,
                floor_u16=o["floor_u16"] if analog else 0,
                period_us=o["period_us"],
            )
        )
