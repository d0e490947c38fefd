"""Published MicroPython drivers for the bus parts (host/core/drivers.txt, fetched pinned
by make setup into build/drivers/), each run unchanged through a firmware written as its
README or examples show, asserting the physics: a servo on a PCA9685 reaches its angle."""

import pytest

from host.core.drivers import driver_folder
from host.rig.app import App
from host.tests.conftest import FIRMWARE, results
from sim_plant.catalogue.assembly import assemble

pytestmark = pytest.mark.hil


def run_driver(make_rig, case: str, plant: dict, driver: str, duration_s: float, probe=None, **app):
    """Run firmware ``case`` with ``driver``'s folder on its path; ``probe(rig)`` (if
    given) is called at each second of virtual time; returns (rig, results, probes)."""
    options = {"wiring": {}, "pins": {}, **app}
    the_app = App(
        name=case,
        default_board="esp32_bench",
        make_plant=lambda: assemble(plant),
        lib_dirs=(driver_folder(driver),),
        console_baud=0,
        **options,
    )
    rig = make_rig(the_app, main_dir=FIRMWARE / case, allow_exit=True)
    probes = []
    for _ in range(int(duration_s)):
        rig.run_for(1.0)
        if probe is not None:
            probes.append(probe(rig))
    rig.stop()
    return rig, results(rig.console), probes


PAN = {
    "body": "bench",
    "parts": [
        {"kind": "servo", "name": "pan", "min_pulse_us": 750, "max_pulse_us": 2250, "range_deg": 180},
        {"kind": "pca9685", "name": "pwm", "bus": "i2c0", "drives": ["pan.pwm"]},
    ],
}


def test_published_pca9685_driver_turns_a_servo_on_channel_0_to_its_angle(make_rig):
    """micropython-pca9685 0.1.0's Servo helper (750 to 2250 us for 180 degrees) on a servo
    of that span: 90 then 30 degrees. The driver sets PRE_SCALE to 25 MHz / 4096 / 50 Hz
    = 122 where the datasheet's formula wants 121 (its frequency is 49.6 Hz, not 50), so
    its pulses are 0.8 % long: the horn is within 1.5 degrees."""
    rig, r, angles = run_driver(
        make_rig, "pca9685_servo", PAN, "micropython-pca9685", 3.0, lambda rig: rig.plant.truth()["pan_angle_deg"]
    )
    assert "angle" in r, rig.console
    assert r["frequency"] == pytest.approx(25e6 / 4096 / 122)
    assert angles[0] == pytest.approx(90, abs=1.5), angles
    assert angles[-1] == pytest.approx(30, abs=1.5), angles
    assert rig.plant.truth()["pwm_freq_hz"] == pytest.approx(25e6 / 4096 / 123)
