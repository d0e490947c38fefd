"""Plant kinds by name, for rig files (``[plant] kind = ...``): each name is a plant
class, or a function that builds one, whose keyword options are the table
``[plant.options]``. Unknown options and bad values are refused with the option's name.

Every robot of ours, and the loopback bench, is now a body and parts from
:mod:`sim_plant.catalogue` (``[plant] body = ...``); no kind is registered. The table stays
for plants a user writes as a class of their own.
"""

import functools
import inspect

from sim_plant.plant import Plant

KINDS: dict = {}


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
