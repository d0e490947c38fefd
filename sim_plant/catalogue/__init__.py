"""The catalogue of parts and bodies a plant is built from (``[plant] body = ...`` and
``[[plant.parts]]`` in a rig file; ``docs/parts.md``).

Every module of this package is looked at: a module that declares a
:class:`~sim_plant.catalogue.base.PartType` or :class:`~sim_plant.catalogue.base.BodyType`
subclass with a ``kind`` is a part or a body, one class per module. Adding a part is
adding its module (and its test): nothing else names it.
"""

import functools
import importlib
import pkgutil

from sim_plant.catalogue.base import BodyType, PartType

NOT_ENTRIES = frozenset(("base", "assembly", "docs"))


@functools.cache
def _entries() -> tuple[dict, dict]:
    parts, bodies = {}, {}
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda i: i.name):
        if info.name in NOT_ENTRIES:
            continue
        module = importlib.import_module(f"{__name__}.{info.name}")
        found = [
            obj
            for obj in vars(module).values()
            if isinstance(obj, type) and obj.__module__ == module.__name__ and issubclass(obj, (PartType, BodyType))
        ]
        if len(found) != 1 or not found[0].kind:
            raise TypeError(f"{module.__name__}: expected one part or body class with a kind, got {found}")
        cls = found[0]
        table = parts if issubclass(cls, PartType) else bodies
        if cls.kind in table:
            raise TypeError(f"{module.__name__}: kind {cls.kind!r} is {table[cls.kind].__module__}'s too")
        table[cls.kind] = cls
    return parts, bodies


def parts() -> dict[str, type]:
    """Part kind -> its class, in name order."""
    return dict(_entries()[0])


def bodies() -> dict[str, type]:
    """Body kind -> its class, in name order."""
    return dict(_entries()[1])
