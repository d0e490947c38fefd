"""The firmware is confined to its board (issue 28, docs/security.md): a received trace
folder runs no firmware the user did not name."""

import json
import shutil
import subprocess
import sys

import pytest

from host.artefacts.folder import reseal
from host.core.errors import ConfigError
from host.core.paths import FIRMWARE, REPO
from host.rig.replay import FirmwareChoice, replay

pytestmark = [pytest.mark.hil, pytest.mark.xdist_group("test_confine")]

HOSTILE_MAIN = """\
import os
print("HOSTILE FIRMWARE RAN")
open("pwned.txt", "w").write("from a trace folder")
"""


@pytest.fixture(scope="module")
def rover_trace(tmp_path_factory):
    """A short recorded rover run (shared by the tests that craft folders from it)."""
    from host.rig import Recording, Rig, RigSpec

    folder = tmp_path_factory.mktemp("rover-seed5")
    with Rig(RigSpec("rover", seed=5), Recording(trace=True, record=True, artefacts=folder)) as rig:
        rig.run_for(1.0)
    return folder


def hostile_folder(rover_trace, tmp_path):
    """A copy of a real trace folder whose header names a rig file with a hostile firmware
    beside it (as a folder handed over by someone else could)."""
    evil = tmp_path / "evil"
    evil.mkdir()
    rig = (FIRMWARE / "apps" / "rover" / "rig.toml").read_text()
    (evil / "rig.toml").write_text(rig)
    (evil / "main.py").write_text(HOSTILE_MAIN)
    trace = tmp_path / "received"
    shutil.copytree(rover_trace, trace)
    header = json.loads((trace / "header.json").read_text())
    header["spec"]["app"] = str(evil / "rig.toml")
    (trace / "header.json").write_text(json.dumps(header))
    reseal(trace)
    return trace, evil


def test_replay_refuses_the_firmware_a_received_folder_names(rover_trace, tmp_path):
    trace, evil = hostile_folder(rover_trace, tmp_path)
    with pytest.raises(ConfigError, match="--trust-folder") as e:
        replay(trace, tmp_path / "replay")
    assert str(evil / "rig.toml") in str(e.value)
    assert not list(tmp_path.rglob("pwned.txt")), "the hostile firmware ran"


def test_replay_runs_the_firmware_the_user_names_and_says_so(rover_trace, tmp_path):
    trace, _evil = hostile_folder(rover_trace, tmp_path)
    ours = FIRMWARE / "apps" / "rover"
    result = replay(trace, tmp_path / "replay", choice=FirmwareChoice(app="rover"))
    assert result.same, result.difference
    assert str(ours) in result.firmware and "--app" in result.firmware, result.firmware
    assert not list(tmp_path.rglob("pwned.txt")), "the hostile firmware ran"


def test_a_header_naming_a_firmware_folder_needs_a_flag_too(rover_trace, tmp_path):
    trace = tmp_path / "received"
    shutil.copytree(rover_trace, trace)
    header = json.loads((trace / "header.json").read_text())
    header["spec"]["main_dir"] = str(tmp_path)
    (trace / "header.json").write_text(json.dumps(header))
    reseal(trace)
    with pytest.raises(ConfigError, match=f"main_dir {tmp_path}"):
        replay(trace, tmp_path / "replay")


def test_mpy_fil_replay_says_which_firmware_and_refuses_a_hostile_one_in_one_line(rover_trace, tmp_path):
    trace, _evil = hostile_folder(rover_trace, tmp_path)
    run = [sys.executable, "-m", "host.cli", "replay", str(trace), "--out", str(tmp_path / "r")]
    done = subprocess.run(run, capture_output=True, text=True, cwd=REPO, timeout=120)
    assert done.returncode == 2 and done.stderr.count("\n") == 1, done.stderr
    assert "HOSTILE" not in done.stdout + done.stderr and not list(tmp_path.rglob("pwned.txt"))
    done = subprocess.run([*run, "--trust-folder"], capture_output=True, text=True, cwd=REPO, timeout=120)
    assert "--trust-folder" in done.stdout, done.stdout + done.stderr  # it says which one it ran
    own = subprocess.run(
        [sys.executable, "-m", "host.cli", "replay", str(rover_trace), "--out", str(tmp_path / "o")],
        capture_output=True,
        text=True,
        cwd=REPO,
        timeout=120,
    )
    assert own.returncode == 0 and "our app rover" in own.stdout, own.stdout + own.stderr
