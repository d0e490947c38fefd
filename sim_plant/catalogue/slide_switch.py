"""Part ``slide_switch``: a single-pole, two-way slide switch: its common pin (the board's
input, ``<name>.out``) meets the left or the right pin, each tied to ground (0) or to the
supply (1) as the wiring has it."""

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.catalogue.potentiometer import Constant
from sim_plant.controls import Control
from sim_plant.option_table import OneOf


class SlideSwitch(PartType):
    kind = "slide_switch"
    doc = "A two-way slide switch: the common pin reads the level of the side the handle is on."
    OPTIONS = (
        Opt("position", OneOf(("left", "right")), "left", "where the handle is"),
        Opt("left_level", OneOf((0, 1)), 0, "the level the left pin is tied to (0: ground, 1: the supply)"),
        Opt("right_level", OneOf((0, 1)), 1, "the level the right pin is tied to"),
    )
    SIGNALS = (Sig("out", "out", "level", "the common pin's level"),)
    TRUTH = ()
    VIEWS = (View("level", "the switch's level", signals=("out",)),)

    CONTROLS = (Control("position", OneOf(("left", "right")), "where the handle is from then on"),)

    def control_change(self, control: str, value) -> tuple | None:
        super().control_change(control, value)
        return f"{self.name}.out", self.options[f"{value}_level"]

    def add(self, build: Build) -> None:
        level = self.options[f"{self.options['position']}_level"]
        build.parts.append(Constant({f"{self.name}.out": level}, {f"{self.name}.out": "level"}))
