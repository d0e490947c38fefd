"""The vl53l1x part (docs/parts.md) under a driver written as the public MicroPython
VL53L1X drivers are (no published one on the package index: host/tests/firmware/tof1_stop),
16-bit register addresses through addrsize=16: the chip boots, the first range is the
wall's along the mount's ray, a range comes every 100 ms (the timing budget), and the robot
stops 0.3 m from the wall."""

import pytest

from host.tests.conftest import FIRMWARE, bench_app, results
from host.tests.test_bus_drivers import MOTORS, SPIN_WIRING

pytestmark = pytest.mark.hil


def test_a_vl53l1x_driver_ranges_the_wall_once_per_budget_and_the_robot_stops_at_it(make_rig):
    tof = {"kind": "vl53l1x", "name": "tof", "bus": "i2c0", "mount": {"x_m": 0.05}}
    plant = {"body": "differential", "start_pose": [2.0, 1.0, 0.0], "parts": [*MOTORS, tof]}
    pins = {"PWMA": 16, "AIN1": 17, "AIN2": 18, "PWMB": 4, "BIN1": 23, "BIN2": 19}
    app = bench_app("tof1", plant, wiring=SPIN_WIRING, pins=pins)
    rig = make_rig(app, main_dir=FIRMWARE / "tof1_stop", allow_exit=True)
    rig.run_for(8.0)
    truth = rig.plant.truth()
    rig.stop()
    r = results(rig.console)
    assert "period_ms" in r, rig.console
    assert 1_200 <= r["boot_us"] < 5_000, "the boot state set after the boot time"
    assert r["first_mm"] == pytest.approx(950, rel=0.03)  # the wall at x = 3 m, the chip at 2.05 m
    assert r["stop_mm"] <= 300
    assert r["period_ms"] == pytest.approx(100, abs=2)
    assert truth["tof_range_m"] == pytest.approx(0.3, abs=0.05), truth["tof_range_m"]
