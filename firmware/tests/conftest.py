"""Firmware unit tests under CPython: the pure modules of the pool cleaner and the lab
robot, and the NMEA driver, imported from where a board has them (the app folders and
lib/; their module names do not clash)."""

import sys
from pathlib import Path

FIRMWARE = Path(__file__).resolve().parent.parent
for folder in (FIRMWARE / "apps" / "pool_cleaner", FIRMWARE / "apps" / "lab_robot", FIRMWARE / "lib"):
    if str(folder) not in sys.path:
        sys.path.insert(0, str(folder))
