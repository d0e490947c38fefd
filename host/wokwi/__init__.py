"""Wokwi projects as rigs moved to ``host/rig/config/wokwi/`` (docs/wokwi.md): a rig's
configuration read from a ``diagram.json``. Their paths of 0.2 (``host.wokwi.project``,
...) still import, each as the same module there."""

from host.core.moved import keep_old_paths

MOVED = ("boards", "diagram", "docs", "parts", "project", "tomlout")
HOST = __name__.rpartition(".")[0]  # (host, or mpy_fil.host where installed)
keep_old_paths(__name__, {name: f"{HOST}.rig.config.wokwi.{name}" for name in MOVED})
