"""Part ``encoder``: a wheel encoder, quadrature (A/B) or a single-channel slotted disk,
on the wheel or on the motor shaft behind a gearbox (:mod:`sim_plant.physics.encoder`)."""

import math

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.option_table import Num, OneOf
from sim_plant.physics.encoder import MISS_GAPS, MissingEdgeEncoder, QuadratureEncoder, SlottedDiskEncoder


class Encoder(PartType):
    kind = "encoder"
    doc = "A wheel encoder: quadrature A/B or one slotted-disk channel, on the wheel or the motor shaft."
    OPTIONS = (
        Opt(
            "channels",
            OneOf(("quadrature", "single")),
            "quadrature",
            "A/B in quadrature (4 counts a line) or one channel (2 edges a slot)",
        ),
        Opt("wheel", OneOf(("left", "right")), "left", "the wheel it turns with"),
        Opt(
            "on", OneOf(("motor", "wheel")), "motor", "the disk on the motor shaft (behind gear_ratio) or on the wheel"
        ),
        Opt(
            "gear_ratio", Num("motor turns per wheel turn", 0.01, 10_000), 20.0, "the gearbox, for a disk on the motor"
        ),
        Opt("lines_per_rev", Num("", 1, 10_000, whole=True), 7, "lines (slots) per revolution of the disk"),
        Opt("polarity", OneOf((-1, 1)), 1, "-1: mounted mirrored, counts backwards when the wheel turns forwards"),
        Opt(
            "missed_edge_p",
            Num("", 0, 0.49),
            0.0,
            "quadrature: chance per edge that the next comes at the same instant (a board's IRQ misses it); "
            "the gaps are drawn from the plant's seed when it is built; the truth adds {name}_missed",
        ),
    )
    SIGNALS = (
        Sig("a", "out", "level", "channel A", (("channels", ("quadrature",)),)),
        Sig("b", "out", "level", "channel B (A leads going forwards)", (("channels", ("quadrature",)),)),
        Sig("out", "out", "level", "the slotted disk's channel", (("channels", ("single",)),)),
    )
    TRUTH = ("{name}_edges",)
    VIEWS = (
        View(
            "count",
            "the edges the firmware counted against the disk's true count",
            signals=("a", "b", "out"),
            truth=("{name}_edges",),
        ),
    )
    needs_body = True

    def check(self) -> None:
        if self.options["missed_edge_p"] > 0 and self.options["channels"] != "quadrature":
            raise ValueError("missed_edge_p: only a quadrature encoder misses edges")

    def metres_per_edge(self, body: dict) -> float | None:
        """The wheel's travel per edge on a body with ``wheel_radius_m`` (None without)."""
        radius = body.get("wheel_radius_m")
        if not radius:
            return None
        o = self.options
        edges = o["lines_per_rev"] * (4 if o["channels"] == "quadrature" else 2)
        return 2 * math.pi * radius / (edges * (o["gear_ratio"] if o["on"] == "motor" else 1.0))

    def add(self, build: Build) -> None:
        o = self.options
        options = {
            "wheel": 0 if o["wheel"] == "left" else 1,
            "lines_per_rev": o["lines_per_rev"],
            "gear_ratio": o["gear_ratio"] if o["on"] == "motor" else 1.0,
            "polarity": o["polarity"],
        }
        if o["channels"] == "quadrature" and o["missed_edge_p"] > 0:
            gaps = tuple(int(g) + 1 for g in build.rng.geometric(o["missed_edge_p"], MISS_GAPS))
            build.encoders.append(MissingEdgeEncoder((f"{self.name}.a", f"{self.name}.b"), gaps=gaps, **options))
        elif o["channels"] == "quadrature":
            build.encoders.append(QuadratureEncoder((f"{self.name}.a", f"{self.name}.b"), **options))
        else:
            build.encoders.append(SlottedDiskEncoder((f"{self.name}.out",), **options))
