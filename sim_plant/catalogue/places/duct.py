"""World ``duct``: seed 002's duct with one right branch (:func:`sim_plant.world.one_right_branch_duct`)."""

from sim_plant import world
from sim_plant.catalogue.base import Opt, WorldType
from sim_plant.duct import DUCT_START
from sim_plant.option_table import length


class Duct(WorldType):
    kind = "duct"
    doc = "A duct with one right branch (seed 002 §5.7); the robot starts 0.3 m in, on its centre line."
    OPTIONS = (Opt("width_m", length(0.05, 10), world.DUCT_WIDTH_M, "the duct's width"),)

    def build(self):
        return world.one_right_branch_duct(self.options["width_m"]), DUCT_START
