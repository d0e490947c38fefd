"""two_sonar_bot in the loop: the firmware in this folder, unchanged, on a robot its rig
file describes part by part (a body, two motors, two encoders, a front and a rear
HC-SR04, an active-high button, an LED probe).

Run with `make test` (or `.venv/bin/pytest examples/two_sonar_bot`)."""

import re
from pathlib import Path

import pytest

RIG = str(Path(__file__).parent / "rig.toml")
pytestmark = pytest.mark.hil
BODY_RADIUS_M = 0.08


def test_the_button_fires_its_rising_edge_irq_at_the_press_not_the_release(make_rig):
    rig = make_rig(RIG, seed=1)
    rig.run_for(0.9)  # pressed at 1.0 s, released at 1.5 s (rig.toml)
    assert rig.truth()["x_m"] == pytest.approx(1.0), "it moved before the start button"
    rig.run_for(0.3)
    found = re.search(r"pressed (\d+) ms after boot", rig.console)
    assert found, rig.console
    assert 1000 <= int(found.group(1)) < 1010, "the IRQ did not fire at the press (1000 ms)"
    assert rig.truth()["x_m"] > 1.0, "pressed, but it did not start"


@pytest.mark.parametrize(("world", "face_m"), [({}, 2.05), ({"obstacles": []}, 3.0)], ids=["box-ahead", "wall-ahead"])
def test_drives_to_the_obstacle_reverses_on_the_rear_sensor_and_stops_before_the_wall(make_rig, world, face_m):
    rig = make_rig(RIG, seed=2, plant_options=world)
    rig.run_for(12)
    assert "obstacle ahead" in rig.console, rig.console
    rig.run_for(16)
    truth = rig.truth()
    assert "stopped" in rig.console, rig.console
    assert truth["contacts"] == [], f"touched at {truth['contacts'][:3]}"
    rear_gap_m = truth["x_m"] - BODY_RADIUS_M
    assert 0.15 < rear_gap_m < 0.30, f"stopped {rear_gap_m:.3f} m from the wall behind (asked: 25 cm)"
    assert truth["v_m_s"] == 0.0
    far_m = float(re.search(r"obstacle ahead at (\d+) cm", rig.console).group(1)) / 100
    assert 0.2 < far_m < 0.3, far_m
    assert truth["sonar_rear_ping_range_m"] == pytest.approx(rear_gap_m, abs=0.03)
    assert truth["sonar_front_ping_t_us"] is not None and face_m > 2.0


def test_the_firmware_counts_what_the_encoders_turned(make_rig):
    rig = make_rig(RIG, seed=3)
    rig.run_for(16)
    counts = re.search(r"counts (-?\d+) (-?\d+)", rig.console)
    assert counts, rig.console
    truth = rig.truth()
    # the firmware counts both edges of channel A: half the quadrature edges
    assert int(counts.group(1)) == pytest.approx(truth["enc_l_edges"] / 2, abs=1)
    assert int(counts.group(2)) == pytest.approx(truth["enc_r_edges"] / 2, abs=1)
    assert truth["enc_l_edges"] < 0, "it ends behind where it started: a net count backwards"
    assert truth["led_changes"] > 100, "the LED probe saw the loop toggle it"
