"""Plant models for the firmware-in-the-loop harness.

Pure Python + numpy: no I/O, no processes, no wall clock. Every plant follows the
contract in :mod:`sim_plant.plant` (reset with a seed, set inputs, advance to a
virtual time, read outputs, ground truth apart from what sensors report). The robots
of the seed documents (``docs/plant.md`` tells which model comes from which seed; the
rover and the vacuum robot of seed 003 are rig files over the parts of
:mod:`sim_plant.catalogue`):

=====================  ==============================================================
class                  robot
=====================  ==============================================================
``PoolCleaner``        WEDA B400 tracked pool cleaner, seeds 000/001
``DuctRobot``          duct inspection robot, seed 002
``LabRobot``           dead-reckoning lab robot with quadrature encoders, seed 004
=====================  ==============================================================
"""

from sim_plant.duct import DuctRobot
from sim_plant.lab_robot import LabRobot
from sim_plant.plant import Change, Plant
from sim_plant.pool import PoolCleaner

__all__ = ["Change", "DuctRobot", "LabRobot", "Plant", "PoolCleaner"]
