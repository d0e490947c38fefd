"""Firmware in the loop: the :class:`Rig` and the parts it delegates to, by job
(``docs/architecture.md`` draws them): ``loop/`` (the run), ``config/`` (rig files, apps,
budgets), ``hardware/`` (the host side of the firmware's peripherals), ``targets/`` (where
the firmware runs, its sandbox) and ``scan/`` (firmware read without running it).

The modules' paths of 0.2 (``host.rig.rigfile``, ``host.rig.budgets``, ...) still import:
each names the same module in its sub-package (:data:`MOVED`)."""

from host.core.moved import keep_old_paths
from host.rig.loop.rig import Rig
from host.rig.loop.spec import Recording, RigSpec

__all__ = ["Recording", "Rig", "RigSpec"]

MOVED = {
    module: package
    for package, modules in {
        "config": "app apps arguments boardfile budgets migrate rigfile rigrules tomlfile verdicts",
        "hardware": "busimage bustrace inputs outputs peripherals pio pio_ahead pio_out pollwatch wiring",
        "loop": "boardset boardview clock endings hostboard introspect manifest messages pacing replay rig session "
        "spec speculation waits",
        "scan": "boards pincheck pinscan starter",
        "targets": "boardfs firmware heap mcutime sandbox target",
    }.items()
    for module in modules.split()
}
"""A module's name of 0.2 (``host.rig.<module>``) -> its sub-package now."""


keep_old_paths(__name__, {name: f"{__name__}.{package}.{name}" for name, package in MOVED.items()})
