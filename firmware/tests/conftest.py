"""Firmware unit tests under CPython: the pool cleaner's and the vacuum robot's pure
modules and the NMEA driver, imported from where a board has them (the app folder, the
app's lib/ and firmware/lib)."""

import sys
from pathlib import Path

FIRMWARE = Path(__file__).resolve().parent.parent
for folder in (FIRMWARE / "apps" / "pool_cleaner", FIRMWARE / "apps" / "vacuum" / "lib", FIRMWARE / "lib"):
    if str(folder) not in sys.path:
        sys.path.insert(0, str(folder))
