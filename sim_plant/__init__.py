"""Plant models for the firmware-in-the-loop harness.

Pure Python + numpy: no I/O, no processes, no wall clock. Every plant follows the
contract in :mod:`sim_plant.plant` (reset with a seed, set inputs, advance to a
virtual time, read outputs, ground truth apart from what sensors report).
"""

from sim_plant.plant import Change, Plant

__all__ = ["Change", "Plant"]
