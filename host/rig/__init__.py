"""Firmware in the loop: the :class:`Rig` and the parts it delegates to, by job
(``docs/architecture.md`` draws them): ``loop/`` (the run), ``config/`` (rig files, apps,
budgets), ``hardware/`` (the host side of the firmware's peripherals), ``targets/`` (where
the firmware runs, its sandbox) and ``scan/`` (firmware read without running it).

The modules' paths of 0.2 (``host.rig.rigfile``, ``host.rig.budgets``, ...) still import:
each names the same module in its sub-package (:data:`MOVED`)."""

import importlib
import importlib.abc
import importlib.util
import sys

from host.rig.loop.rig import Rig
from host.rig.loop.spec import Recording, RigSpec

__all__ = ["Recording", "Rig", "RigSpec"]

MOVED = {
    module: package
    for package, modules in {
        "config": "app apps arguments boardfile budgets migrate rigfile rigrules tomlfile verdicts",
        "hardware": "busimage bustrace inputs outputs peripherals pio pio_out pollwatch wiring",
        "loop": "boardset boardview clock endings hostboard introspect manifest messages pacing replay rig session "
        "spec speculation waits",
        "scan": "boards pincheck pinscan starter",
        "targets": "boardfs firmware heap mcutime sandbox target",
    }.items()
    for module in modules.split()
}
"""A module's name of 0.2 (``host.rig.<module>``) -> its sub-package now."""


class _Alias(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """``import host.rig.rigfile`` gives ``host.rig.config.rigfile`` itself (one module,
    under both names), imported only when asked for."""

    def find_spec(self, fullname, path=None, target=None):
        parent, _, name = fullname.rpartition(".")
        if parent == __name__ and name in MOVED:
            return importlib.util.spec_from_loader(fullname, self)
        return None

    def create_module(self, spec):
        name = spec.name.rpartition(".")[2]
        module = importlib.import_module(f"{__name__}.{MOVED[name]}.{name}")
        spec.loader_state = module.__spec__
        return module

    def exec_module(self, module):
        module.__spec__ = module.__spec__.loader_state  # (the import system gave it the old name's spec)


if not any(isinstance(f, _Alias) for f in sys.meta_path):
    sys.meta_path.append(_Alias())
