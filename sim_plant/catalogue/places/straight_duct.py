"""World ``straight_duct``: a straight duct closed at both ends (:func:`sim_plant.duct.straight_duct`)."""

from sim_plant import world
from sim_plant.catalogue.base import Opt, WorldType
from sim_plant.duct import DUCT_START, straight_duct
from sim_plant.option_table import length


class StraightDuct(WorldType):
    kind = "straight_duct"
    doc = "A straight duct along +x closed at both ends (seed 002 §5.4); the robot starts 0.3 m in."
    OPTIONS = (
        Opt("length_m", length(0.5, 100), 1.5, "the duct's length"),
        Opt("width_m", length(0.05, 10), world.DUCT_WIDTH_M, "the duct's width"),
    )

    def build(self):
        return straight_duct(self.options["length_m"], self.options["width_m"]), DUCT_START
