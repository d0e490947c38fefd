"""Plant models for the firmware-in-the-loop harness.

Pure Python + numpy: no I/O, no processes, no wall clock. Every plant follows the
contract in :mod:`sim_plant.plant` (reset with a seed, set inputs, advance to a
virtual time, read outputs, ground truth apart from what sensors report). The robots
of the seed documents (``docs/plant.md`` tells which model comes from which seed):

=====================  ==============================================================
class                  robot
=====================  ==============================================================
``RoverRoom``          round differential-drive rover in a room (the first HIL plant)
``VacuumRobot``        vacuum cleaner robot with an HC-SR04 on a servo, seed 003
``LabRobot``           dead-reckoning lab robot with quadrature encoders, seed 004
=====================  ==============================================================

The WEDA B400 tracked pool cleaner of seeds 000/001 and seed 002's duct inspection robot
are rig files over catalogue parts (:mod:`sim_plant.catalogue`; their figures in
:mod:`sim_plant.pool` and :mod:`sim_plant.duct`).
"""

from sim_plant.lab_robot import LabRobot
from sim_plant.plant import Change, Plant
from sim_plant.rover import RoverRoom
from sim_plant.vacuum import VacuumRobot

__all__ = ["Change", "LabRobot", "Plant", "RoverRoom", "VacuumRobot"]
