"""World ``canyon``: a winding canyon (:func:`sim_plant.world.canyon`)."""

from sim_plant import world
from sim_plant.catalogue.base import Opt, WorldType
from sim_plant.option_table import length


class Canyon(WorldType):
    kind = "canyon"
    doc = "A winding canyon between two walls (the lab robot's wall following)."
    OPTIONS = (Opt("width_m", length(0.1, 10), world.CANYON_WIDTH_M, "the canyon's width"),)

    def build(self):
        return world.canyon(self.options["width_m"]), (0.3, 0.0, 0.0)
