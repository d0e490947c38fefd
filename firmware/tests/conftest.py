<<<<<<< HEAD
"""Firmware unit tests under CPython: the pure modules of the pool cleaner and the lab
robot, and the NMEA driver, imported from where a board has them (the app folders and
lib/; their module names do not clash)."""
=======
"""Firmware unit tests under CPython: the pool cleaner's and the vacuum robot's pure
modules and the NMEA driver, imported from where a board has them (the app folder, the
app's lib/ and firmware/lib)."""
>>>>>>> issue-vacuum

import sys
from pathlib import Path

FIRMWARE = Path(__file__).resolve().parent.parent
<<<<<<< HEAD
for folder in (FIRMWARE / "apps" / "pool_cleaner", FIRMWARE / "apps" / "lab_robot", FIRMWARE / "lib"):
=======
for folder in (FIRMWARE / "apps" / "pool_cleaner", FIRMWARE / "apps" / "vacuum" / "lib", FIRMWARE / "lib"):
>>>>>>> issue-vacuum
    if str(folder) not in sys.path:
        sys.path.insert(0, str(folder))
