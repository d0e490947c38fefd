"""Plant kinds by name, for rig files (``[plant] kind = "lab_robot"``): each name is a
plant class, or a function that builds one, whose keyword options are the table
``[plant.options]``. Unknown options and bad values are refused with the option's name.
"""

import functools
import inspect

from sim_plant.duct import DuctRobot
from sim_plant.lab_robot import LabRobot
from sim_plant.plant import Plant
from sim_plant.pool import BODY_LENGTH_M, BODY_WIDTH_M, PoolCleaner
from sim_plant.wires import wires
from sim_plant.world import POOL_LENGTH_M


def pool_cleaner(**options) -> PoolCleaner:
    """The pool cleaner as its mission starts (seed 000 §7.3.3): in a corner, the front
    bumper (bumper1) 1 cm off the end wall, its side 2 cm off the side wall."""
    length_m = options.get("pool_length_m", POOL_LENGTH_M)
    options.setdefault("start_pose", (length_m - BODY_LENGTH_M / 2 - 0.01, BODY_WIDTH_M / 2 + 0.02, 0.0))
    return PoolCleaner(**options)


pool_cleaner.options_of = PoolCleaner

KINDS = {
    "pool_cleaner": pool_cleaner,
    "duct_robot": DuctRobot,
    "lab_robot": LabRobot,
    "wires": wires,  # a loopback bench: board outputs wired to board inputs
}


@functools.cache
def options(kind: str) -> dict[str, object]:
    """The kind's options and their defaults (``inspect.Parameter.empty``: required)."""
    make = KINDS[kind]
    params = inspect.signature(getattr(make, "options_of", make)).parameters.values()
    return {p.name: p.default for p in params if p.kind in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD)}


def make(kind: str, **opts) -> Plant:
    """A plant of ``kind`` with ``opts``; KeyError for an unknown kind, TypeError naming
    an unknown option, ValueError for a value the plant refuses."""
    if kind not in KINDS:
        raise KeyError(kind)
    unknown = sorted(set(opts) - set(options(kind)))
    if unknown:
        raise TypeError(f"unknown option {', '.join(unknown)} (options: {', '.join(sorted(options(kind)))})")
    return KINDS[kind](**opts)
