"""World ``multi_branch_duct``: a duct of several branches (:func:`sim_plant.world.multi_branch_duct`)."""

from sim_plant import world
from sim_plant.catalogue.base import Opt, WorldType
from sim_plant.duct import DUCT_START
from sim_plant.option_table import length


class MultiBranchDuct(WorldType):
    kind = "multi_branch_duct"
    doc = "A duct of several branches; the robot starts 0.3 m in, on its centre line."
    OPTIONS = (Opt("width_m", length(0.05, 10), world.DUCT_WIDTH_M, "the duct's width"),)

    def build(self):
        return world.multi_branch_duct(self.options["width_m"]), DUCT_START
