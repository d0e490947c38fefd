"""oled_bot in the loop: the firmware in this folder, unchanged, on the robot its rig file
describes (a differential body on a TB6612, an LSM6DSOX, a VL53L0X and an SSD1306 on one
I2C bus), in virtual time: it turns a quarter turn by its gyro, drives to the wall and
stops by its ranger, and its OLED shows what it is doing.

Run with `make test` (or `.venv/bin/pytest examples/oled_bot`)."""

import math
from pathlib import Path

import pytest

RIG = str(Path(__file__).parent / "rig.toml")
pytestmark = pytest.mark.hil
WALL_Y_M = 2.0  # rig.toml's room: 2 m deep
TOF_AHEAD_M = 0.06  # the ranger's mount ahead of the body's centre


def oled(rig):
    inner = getattr(rig.plant, "inner", rig.plant)
    return next(p for p in inner.parts if getattr(p, "label", "") == "oled")


def lit_in_rows(picture: bytes, y0: int, y1: int) -> int:
    return sum(picture[y0 * 128 : y1 * 128])


def test_turns_a_quarter_turn_by_its_gyro_then_stops_at_the_wall_by_its_ranger(make_rig):
    rig = make_rig(RIG, seed=1)
    rig.run_for(1.5)
    assert "oled_bot: turned" in rig.console, rig.console
    heading_deg = math.degrees(rig.truth()["theta_rad"])
    assert heading_deg == pytest.approx(90, abs=3), "the integrated gyro turned it a quarter turn"
    rig.run_for(8.5)
    assert "oled_bot: stopped at" in rig.console, rig.console
    truth = rig.truth()
    gap_m = WALL_Y_M - truth["y_m"] - TOF_AHEAD_M * math.sin(truth["theta_rad"])
    assert gap_m == pytest.approx(0.25, abs=0.03), f"stopped {gap_m:.3f} m from the wall"
    assert truth["contacts"] == []
    assert rig.budgets["ranging"].stats()["p50"] == pytest.approx(33_000, abs=2_500)
    rig.budgets["gyro_read"].check()
    assert rig.budgets["gyro_read"].stats()["max"] == 120, "readfrom_mem of 2 bytes at 400 kHz"


def test_the_oled_shows_the_robots_state(make_rig):
    rig = make_rig(RIG, seed=1)
    rig.run_for(0.3)
    turning = oled(rig).picture()
    rig.run_for(9.7)
    stopped = oled(rig).picture()
    assert lit_in_rows(turning, 0, 8) == lit_in_rows(stopped, 0, 8) > 50, "the title on the first text row"
    assert lit_in_rows(turning, 12, 20) != lit_in_rows(stopped, 12, 20), "TURN 90, then STOP"
    assert lit_in_rows(turning, 24, 32) == 0 and lit_in_rows(stopped, 24, 32) > 30, "the wall's range when stopped"
    assert rig.truth()["oled_frames"] >= 4, "blank, TURN, DRIVE, ..., STOP"
