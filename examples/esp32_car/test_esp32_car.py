"""esp32_car in the loop: the firmware in this folder, unchanged, on the car its rig file
describes part by part (an ackermann body, a rear motor on an L298N, a steering servo, a
front HC-SR04, a battery divider on GPIO 34, the LED as a probe), in virtual time.

Run with `make test` (or `.venv/bin/pytest examples/esp32_car`)."""

import math
import re
from pathlib import Path

import pytest

RIG = str(Path(__file__).parent / "rig.toml")
pytestmark = pytest.mark.hil
BOX = (2.4, 2.8, 0.7, 1.3)  # rig.toml's obstacle: x0, x1, y0, y1 in m
CENTER_DEG, LEFT_DEG = 90, 130  # main.py's servo angles
LOW_V = 7.0


def test_it_steers_left_around_the_box_ahead_without_touching_it(make_rig):
    rig = make_rig(RIG, seed=1)
    steer_deg, passed_at = [], None
    for step in range(40):  # 10 s, a look every 0.25 s
        rig.run_for(0.25)
        truth = rig.truth()
        steer_deg.append(truth["steer_angle_deg"])
        if passed_at is None and truth["x_m"] > BOX[1]:
            passed_at = (step + 1) * 0.25
    truth = rig.truth()
    found = re.search(r"obstacle at (\d+) cm: steering left", rig.console)
    assert found, rig.console
    assert 30 <= int(found.group(1)) < 50, "it reacted at the range main.py asks (under 50 cm)"
    assert max(steer_deg) == pytest.approx(LEFT_DEG, abs=1), "the servo reached full left"
    assert steer_deg[0] == pytest.approx(CENTER_DEG, abs=1) and steer_deg[-1] == pytest.approx(CENTER_DEG, abs=1)
    assert truth["contacts"] == [], f"touched at {truth['contacts'][:3]}"
    assert passed_at is not None and truth["y_m"] > BOX[3], "it went past the box on its left (+y) side"
    assert math.degrees(truth["theta_rad"]) > 20, "it turned left"


def test_it_reports_the_battery_it_reads_through_the_divider(make_rig):
    rig = make_rig(RIG, seed=2, plant_options={"obstacles": []})
    rig.run_for(5.05)
    reports = [float(v) for v in re.findall(r"battery (\d+\.\d+) V", rig.console)]
    assert len(reports) >= 4, rig.console
    assert reports == sorted(reports, reverse=True), "the voltage only falls"
    assert reports[-1] == pytest.approx(rig.truth()["batt_v"], abs=0.06), "the last report is the battery's voltage"


def test_the_low_battery_led_lights_when_the_battery_drains_below_7_v(make_rig):
    rig = make_rig(RIG, seed=3, plant_options={"obstacles": []})
    crossed_s = None
    for step in range(1, 90):  # up to 36 s, a look every 0.4 s
        rig.run_for(0.4)
        truth = rig.truth()
        if truth["batt_v"] > LOW_V + 0.03:
            assert truth["led_value"] == 0, f"the LED lit at {truth['batt_v']:.2f} V"
        elif crossed_s is None and truth["batt_v"] < LOW_V:
            crossed_s = step * 0.4
        if crossed_s is not None and step * 0.4 >= crossed_s + 0.4:
            break
    assert crossed_s is not None, f"the battery never drained below {LOW_V} V: {truth['batt_v']:.2f} V"
    assert truth["led_value"] == 1, f"{truth['batt_v']:.2f} V and the LED is off"
    assert truth["led_changes"] == 1, "it lit once and stayed lit"
    low = re.search(r"low battery (\d+\.\d+) V", rig.console)
    assert low and LOW_V - 0.1 < float(low.group(1)) <= LOW_V, rig.console  # (printed to 2 places)
