"""pico_bot in the loop: the firmware in this folder, unchanged, on a simulated robot.

Run with `make test` (or `.venv/bin/pytest examples/pico_bot`). The rig file beside it
says which plant, which pins and which budgets."""

from pathlib import Path

import pytest

RIG = str(Path(__file__).parent / "rig.toml")
pytestmark = pytest.mark.hil


def test_waits_for_the_start_button_then_drives(make_rig):
    rig = make_rig(RIG, seed=1)
    rig.run_for(0.9)  # the button is pressed 1 s in
    assert rig.truth()["x_m"] == pytest.approx(0.4), "it moved before the start button"
    assert "pico_bot: press start" in rig.console
    rig.run_for(1.6)
    assert "pico_bot: go" in rig.console
    assert rig.truth()["x_m"] > 0.6, rig.truth()


@pytest.mark.parametrize("world", [{}, {"obstacles": []}], ids=["box-ahead", "open-room"])
def test_turns_away_before_touching_anything(make_rig, world):
    rig = make_rig(RIG, seed=2, plant_options=world)
    rig.run_for(30)
    truth = rig.truth()
    assert truth["contacts"] == [], f"touched at {truth['contacts'][:3]}"
    assert rig.console.count("turning") >= 2, rig.console
    assert truth["distance_m"] > 3.0, truth


def test_control_loop_keeps_its_50ms_period(make_rig):
    rig = make_rig(RIG, seed=3)
    rig.run_for(20)
    loop = rig.budgets["loop"]
    loop.check()
    assert loop.stats()["count"] > 350
