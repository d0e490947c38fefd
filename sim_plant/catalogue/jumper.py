"""Part ``jumper``: a jumper from a board input to ground (a program or option jumper):
the pin reads 0 when it is fitted, 1 (its pull-up) when it is not
(:class:`sim_plant.physics.button.Jumper`)."""

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.option_table import Flag
from sim_plant.physics.button import Jumper as JumperLine


class Jumper(PartType):
    kind = "jumper"
    doc = "A jumper from a board input to ground: reads 0 when fitted, 1 on the pull-up when open."
    OPTIONS = (Opt("fitted", Flag(), False, "the jumper is fitted (the pin reads 0)"),)
    SIGNALS = (Sig("out", "out", "level", "the pin's level: 0 fitted, 1 open"),)
    TRUTH = ()
    VIEWS = (View("level", "the jumper's level", signals=("out",)),)

    def add(self, build: Build) -> None:
        build.parts.append(JumperLine(f"{self.name}.out", self.options["fitted"]))
