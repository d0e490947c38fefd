"""World ``pool``: a rectangular pool, walls all round (:func:`sim_plant.world.pool`)."""

from sim_plant import world
from sim_plant.catalogue.base import Opt, WorldType
from sim_plant.option_table import length


class Pool(WorldType):
    kind = "pool"
    doc = "A rectangular pool, walls all round (the pool cleaner's, seeds 000/001)."
    OPTIONS = (
        Opt("length_m", length(0.1, 1000), world.POOL_LENGTH_M, "the pool's length (x)"),
        Opt("width_m", length(0.1, 1000), world.POOL_WIDTH_M, "the pool's width (y)"),
    )

    def build(self):
        return world.pool(self.options["length_m"], self.options["width_m"]), (1.0, 1.0, 0.0)
