"""Seed 002's Linux master as built (§3.4, §4.5): a host program on the set's clock. Every
10 ms it writes the wheels' set speeds to the MCU (taking its speed records with them),
reads the sonars, the slot totals and the records over I2C, keeps the odometry from the
records (the seed's off-board "raw speed data into positional data") and runs the recursive
exploration, the same duct_nav.py the one-board firmware runs (firmware/apps/duct/lib/).
Its rig file: firmware/apps/duct/as_built.toml."""

import struct
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "firmware" / "apps" / "duct" / "lib"))
from duct_nav import DONE, Explorer  # noqa: E402  (the firmware's own modules, run on the master)
from duct_odometry import Odometry  # noqa: E402

ADDR = 0x0B
TAKE = 1
STEP_MS = 10


def main(board):
    i2c = board.i2c("i2c0", freq=100_000)

    def log(what, odo, *point):
        extra = (" at (%.0f, %.0f) mm" % point) if point else ""
        board.print(
            "%s at %d ms: x %.0f mm y %.0f mm theta %.1f deg%s"
            % (what, board.ticks_ms(), odo.x_mm, odo.y_mm, odo.theta * 57.29578, extra)
        )

    odo = Odometry()
    nav = Explorer(odo, log)
    board.sleep_ms(20)  # the MCU up (its target made)
    board.print("gumstix: exploring, polling the MCU at 0x%02x every %d ms" % (ADDR, STEP_MS))
    speeds = (0, 0)
    while nav.state != DONE:
        i2c.writeto_mem(ADDR, 16, struct.pack("<hhB", speeds[0], speeds[1], TAKE))
        regs = i2c.readfrom_mem(ADDR, 0, 64)
        total_l, total_r, front, left, right, n = struct.unpack_from("<IIBBBB", regs, 0)
        for i in range(n):
            odo.update(*struct.unpack_from("<hh", regs, 32 + 4 * i))
        speeds = nav.step(front, left, right, total_l, total_r)
        board.sleep_ms(STEP_MS)
    i2c.writeto_mem(ADDR, 16, struct.pack("<hhB", 0, 0, TAKE))
    board.print("explored: %d branches found, %d ends, %d left in the list" % (nav.found, nav.ends, len(nav.branches)))
