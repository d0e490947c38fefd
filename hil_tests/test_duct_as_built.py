"""Seed 002's duct robot as it was built (docs/duct.md, "As built"): its MCU's firmware
(firmware/apps/duct/robostix.py) an I2C target of its Linux master, the Gumstix, a host
program on the same clock (duct_as_built/gumstix.py) that runs the exploration the
one-board firmware runs. The seed's figures for the one-board robot hold for it too: the
single right branch explored and home within 150 mm, odometry within 50 mm over 1 m."""

import math
from pathlib import Path

import pytest

from host.core.paths import REPO
from host.rig.config.boardfile import boards_from_data
from host.rig.config.tomlfile import read_toml
from host.rig.loop.boardset import BoardSet

RIG = REPO / "firmware" / "apps" / "duct" / "as_built.toml"
START = (0.3, 0.2)
HOME_TOLERANCE_M = 0.15

pytestmark = pytest.mark.hil


def run_until(boards, text: str, limit_s: float) -> bool:
    while text not in boards["gumstix"].console and boards.t_us < limit_s * 1e6:
        boards.run_for(1.0)
    return text in boards["gumstix"].console


def where(boards) -> str:
    return (
        f"seed {boards.seed}; the master's console:\n{boards['gumstix'].console[-1500:]}\nartefacts: {boards.artefacts}"
    )


def test_the_single_right_branch_is_explored_and_the_robot_comes_home(make_boards, record_property):
    boards = make_boards(RIG, seed=1)
    done = run_until(boards, "explored:", 90)
    truth = boards.truth()
    off = math.hypot(truth["x_m"] - START[0], truth["y_m"] - START[1])
    record_property(
        "result", f"as built (MCU + master on I2C): {off * 1000:.0f} mm from the start at {boards.t_us / 1e6:.0f} s"
    )
    assert done and "explored: 1 branches found, 2 ends, 0 left in the list" in boards["gumstix"].console, where(boards)
    assert off <= HOME_TOLERANCE_M, f"expected home within 150 mm, got {off * 1000:.0f} mm; {where(boards)}"
    boards["robostix"].budgets["control.period"].check()
    assert "e-stop" not in boards["robostix"].console, where(boards)


def test_straight_1m_duct_odometry_of_the_master_within_50mm(tmp_path, record_property):
    """§5.4's first run (centred, square) through the straight duct: the master's odometry,
    kept from the MCU's speed records read over I2C, within 50 mm of the robot at the end."""
    data = read_toml(RIG, "rig file", 1 << 20)
    data["plant"]["world"] = "straight_duct"
    with BoardSet(boards_from_data(RIG, data), seed=1, artefacts=tmp_path) as boards:
        assert run_until(boards, "duct end", 20), f"expected the duct end within 20 s; {where(boards)}"
        line = next(x for x in boards["gumstix"].console.splitlines() if x.startswith("duct end"))
        fx = float(line.split(" x ")[1].split(" mm")[0])
        fy = float(line.split(" mm y ")[1].split(" mm")[0])
        truth = boards.truth()
    tx, ty = (truth["x_m"] - START[0]) * 1000, (truth["y_m"] - START[1]) * 1000
    error = math.hypot(fx - tx, fy - ty)
    record_property("result", f"as built: travelled {tx:.0f} mm, the master's odometry error {error:.1f} mm")
    assert tx > 950 and error <= 50, f"expected ~1 m and odometry within 50 mm: ({fx}, {fy}) vs ({tx:.0f}, {ty:.0f})"


def test_the_master_is_a_host_program_and_the_mcu_firmware_is_board_code():
    """(The master's file is no firmware: it is not in the MCU's flash.)"""
    from host.rig.targets.boardfs import flash_files

    flashed = {name for name, _ in flash_files(RIG.parent)[0]}
    assert "robostix.py" in flashed and not any("gumstix" in name for name in flashed), sorted(flashed)
    assert Path(REPO, "hil_tests", "duct_as_built", "gumstix.py").is_file()
