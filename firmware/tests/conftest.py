"""Firmware unit tests under CPython: the pool cleaner's pure modules and the NMEA
driver, imported from where a board has them (the app folder and lib/)."""

import sys
from pathlib import Path

FIRMWARE = Path(__file__).resolve().parent.parent
for folder in (FIRMWARE / "apps" / "pool_cleaner", FIRMWARE / "lib"):
    if str(folder) not in sys.path:
        sys.path.insert(0, str(folder))
