"""Part ``placement``: a box put in the world at a time (a door closing, a chair pushed
in the way); the body's contacts are checked against it at once. One table a box."""

from sim_plant.catalogue.base import Build, Opt, PartType, View
from sim_plant.contacts import ContactMonitor
from sim_plant.engine import Part
from sim_plant.option_table import BOX, TIME
from sim_plant.plant import NEVER_US
from sim_plant.world import World, box, polygon_segments


class _Placer(Part):
    FIXED_STATE = ("box", "inputs", "outputs")

    def __init__(self, label: str, t_us: int, corners):
        self.label = label
        self.box = corners
        self.next_us = t_us
        self.placed = False

    def fire(self, t_us: int, plant, out: list) -> None:
        world = plant.world
        plant.world = World([*world.segments(), *polygon_segments(self.box)], name=world.name)
        self.placed = True
        self.next_us = NEVER_US
        for part in plant.parts:
            if isinstance(part, ContactMonitor):
                part.recheck(t_us)

    def truth(self, t_us: int, plant) -> dict:
        return {f"{self.label}_placed": self.placed}


class Placement(PartType):
    kind = "placement"
    doc = "A box put in the world at a time (a door closing, a chair pushed in the way)."
    OPTIONS = (
        Opt("t_s", TIME, 0.0, "when it appears"),
        Opt("box", BOX, [1.0, 1.0, 0.2, 0.2], "where: [cx_m, cy_m, w_m, h_m]"),
    )
    TRUTH = ("{name}_placed",)
    VIEWS = (View("level", "whether the box is there yet", truth=("{name}_placed",)),)
    needs_body = True

    def add(self, build: Build) -> None:
        o = self.options
        build.parts.append(_Placer(self.name, round(o["t_s"] * 1e6), box(*o["box"])))
