"""A rig driven call by call, from a test, a notebook, a debugger or an agent over MCP
(``docs/live.md``): :class:`LiveRig`, and the snapshots it goes back to."""

from host.live.journal import Snapshot
from host.live.live import LiveRig

__all__ = ["LiveRig", "Snapshot"]
