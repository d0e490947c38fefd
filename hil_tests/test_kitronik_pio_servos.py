"""Kitronik's own library (``kitronikpicoautonomousroboticsplatform``, pinned in
host/core/drivers.txt) on the ``kitronik_buggy`` kit's rig: its four servos are PIO state
machines counting out 20 ms periods at 2 MHz (docs/kits.md). The servos' pulses reach the
plant as a machine.PWM's would (docs/shim.md, "PIO", outputs): a horn goes where the
library's angle says, in a few wall seconds for a simulated second (the counting loops
jumped over: sim_plant/pio/block.py)."""

import shutil
import time

import pytest

from host.core.drivers import DriverMissing, driver_folder
from host.core.paths import REPO

pytestmark = pytest.mark.hil

RIG = REPO / "host" / "kits" / "kitronik_buggy" / "rig.toml"
FIRMWARE = """
import time
from PicoAutonomousRobotics import KitronikPicoRobotBuggy

buggy = KitronikPicoRobotBuggy()  # (every servo registered and sent to 90 degrees)
buggy.goToPosition(1, 45)
buggy.goToPosition(2, 135)
buggy.goToPeriod(3, 2500)
time.sleep_ms(150)
print("placed")
time.sleep_ms(850)
print("done")
"""
# servo -> (angle, pulse µs) as the library computes them (goToPosition: degrees * 2000 / 180 + 500)
WANT = {"servo1": (90.0, 1500), "servo2": (45.0, 1000), "servo3": (135.0, 2000), "servo4": (180.0, 2500)}


def test_kitronik_library_servos_turn_to_the_angles_it_sends(make_rig, tmp_path):
    try:
        library = driver_folder("kitronikpicoautonomousroboticsplatform") / "PicoAutonomousRobotics.py"
    except DriverMissing as e:
        pytest.skip(str(e))
    shutil.copy(library, tmp_path / "PicoAutonomousRobotics.py")
    (tmp_path / "main.py").write_text(FIRMWARE)
    shutil.copy(RIG, tmp_path / "rig.toml")
    cpu = time.process_time()
    rig = make_rig(str(tmp_path / "rig.toml"), allow_exit=True)
    rig.expect("placed\n")
    truth = rig.truth()
    rig.expect("done\n")
    cpu = time.process_time() - cpu
    where = f"console:\n{rig.console}\nartefacts: {rig.artefacts}"
    for servo, (angle, pulse_us) in WANT.items():
        got_pulse, got_angle = truth[f"{servo}_pulse_us"], truth[f"{servo}_angle_deg"]
        assert abs(got_pulse - pulse_us) < 2, f"{servo}: expected a {pulse_us} µs pulse, got {got_pulse}; {where}"
        assert abs(got_angle - angle) < 1, f"{servo}: expected the horn at {angle} degrees, got {got_angle}; {where}"
    # (stepped one instruction at a time the four state machines took ~20 s of the host's CPU here)
    assert cpu < 8, f"the host took {cpu:.1f} s of CPU for 1 simulated second; {where}"
