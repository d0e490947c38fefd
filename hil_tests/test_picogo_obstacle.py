"""The Pico-Go's IR obstacle sensors (the ``ir_proximity`` part on GP2 and GP3): driven at
the wall, the firmware's loop sees a sensor go low once the wall is within the rig's
threshold and stops (hil_tests/firmware/picogo_obstacle, in the demos' style). With
nothing on those pins they read 0, "blocked", from the start."""

import re
import shutil
from pathlib import Path

import pytest

pytestmark = pytest.mark.hil
FIRMWARE = Path(__file__).parent / "firmware"


def test_picogo_stops_when_its_ir_obstacle_sensors_see_the_wall(make_rig, tmp_path):
    folder = tmp_path / "picogo_obstacle"
    shutil.copytree(FIRMWARE / "picogo_obstacle", folder)
    rig = (FIRMWARE / "picogo" / "rig.toml").read_text()
    (folder / "rig.toml").write_text(rig.replace("start_pose = [0.5, 1.0, 0.0]", "start_pose = [2.5, 1.0, 0.0]"))
    rig = make_rig(str(folder / "rig.toml"), allow_exit=True)
    assert rig.expect(r"start (\d) (\d)").groups() == ("1", "1"), "the wall 0.45 m away: not near"
    dsl, dsr, _t = rig.expect(r"blocked (\d) (\d) (\d+)").groups()
    truth = rig.truth()
    where = f"console:\n{rig.console}\ntruth: {truth}"
    assert (dsl, dsr) == ("0", "0") and truth["dsl_near"] and truth["dsr_near"], where
    rig.expect("done")
    truth = rig.truth()
    assert 0.07 < truth["dsl_range_m"] <= 0.15 and not truth["contacts"], (
        f"stopped within the threshold, 15 cm, short of the wall (the robot coasts after the stop): {where}"
    )
    assert re.search(r"^blocked", rig.console, re.M), where
