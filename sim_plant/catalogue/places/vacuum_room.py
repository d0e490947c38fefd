"""World ``vacuum_room``: the vacuum robot's furnished room (:func:`sim_plant.world.vacuum_room`)."""

from sim_plant import world
from sim_plant.catalogue.base import WorldType


class VacuumRoom(WorldType):
    kind = "vacuum_room"
    doc = "The vacuum robot's room with its furniture (seed 003)."

    def build(self):
        return world.vacuum_room(), (0.5, 0.5, 0.0)
