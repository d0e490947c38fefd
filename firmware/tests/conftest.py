"""Firmware unit tests under CPython: the pure modules of the pool cleaner, the lab robot
and the vacuum robot, and the NMEA driver, imported from where a board has them (the app
folders, the vacuum's lib/ and firmware/lib; their module names do not clash)."""

import sys
from pathlib import Path

FIRMWARE = Path(__file__).resolve().parent.parent
for folder in (
    FIRMWARE / "apps" / "pool_cleaner",
    FIRMWARE / "apps" / "lab_robot",
    FIRMWARE / "apps" / "vacuum" / "lib",
    FIRMWARE / "apps" / "duct" / "lib",
    FIRMWARE / "lib",
):
    if str(folder) not in sys.path:
        sys.path.insert(0, str(folder))
