"""Plant models for the firmware-in-the-loop harness.

Pure Python + numpy: no I/O, no processes, no wall clock. Every plant follows the
contract in :mod:`sim_plant.plant` (reset with a seed, set inputs, advance to a
virtual time, read outputs, ground truth apart from what sensors report). The robots
of the seed documents (``docs/plant.md`` tells which model comes from which seed) are
rig files over catalogue parts (:mod:`sim_plant.catalogue`): the WEDA B400 tracked pool
cleaner of seeds 000/001, seed 002's duct inspection robot, the rover, seed 003's vacuum
robot and seed 004's dead-reckoning lab robot (the pool's and the duct's figures in
:mod:`sim_plant.pool` and :mod:`sim_plant.duct`).
"""

from sim_plant.plant import Change, Plant

__all__ = ["Change", "Plant"]
