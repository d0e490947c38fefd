"""Firmware in the loop: the :class:`Rig` and the parts it delegates to (the target the
firmware runs on, the pacing of its clock, speculation, wiring, inputs and outputs,
budgets), the apps it knows, and replays. ``docs/architecture.md`` draws them."""

from host.rig.rig import Rig
from host.rig.spec import Recording, RigSpec

__all__ = ["Recording", "Rig", "RigSpec"]
