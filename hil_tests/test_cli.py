"""mpy-fil end to end: run the rover in a world, replay its trace, plot it."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from host.artefacts.folder import reseal

pytestmark = pytest.mark.hil

MPY_FIL = Path(sys.executable).parent / "mpy-fil"


def mpy_fil(*args: str) -> subprocess.CompletedProcess:
    assert MPY_FIL.is_file(), f"expected the mpy-fil script at {MPY_FIL} (pyproject [project.scripts]; make setup)"
    return subprocess.run([str(MPY_FIL), *args], capture_output=True, text=True, timeout=120)


def test_run_replay_and_plot_a_rover_mission_from_the_command_line(tmp_path):
    out = tmp_path / "run"
    done = mpy_fil("run", "--world", "small-room", "--seed", "4", "--duration", "8", "--out", str(out), "--no-plots")
    assert done.returncode == 0, f"mpy-fil run failed:\n{done.stdout}{done.stderr}"
    assert f"trace folder: {out}" in done.stdout and "control.period" in done.stdout, done.stdout
    header = json.loads((out / "header.json").read_text())
    assert header["world"]["name"] == "room 3 x 3 m" and header["seed"] == 4 and header["t_end_us"] == 8_000_000
    assert header["plant_options"]["start_pose"] == [1.0, 1.5, 0.0], header["plant_options"]

    done = mpy_fil("replay", str(out))
    assert done.returncode == 0, f"replay of {out} differs:\n{done.stdout}{done.stderr}"
    assert "same outputs" in done.stdout and (out / "replay" / "signals.csv").is_file(), done.stdout

    (out / "signals.csv").write_text((out / "signals.csv").read_text().replace(",motor_r.pwm,", ",motor_r.pwm,1", 1))
    reseal(out)  # (an edit on purpose: else the digests refuse the folder)
    done = mpy_fil("replay", str(out), "--out", str(tmp_path / "replay2"))
    assert done.returncode == 1 and "outputs differ: first difference at output #" in done.stdout, done.stdout

    done = mpy_fil("plot", str(out), "--out", str(tmp_path / "plots"))
    assert done.returncode == 0, done.stderr
    pngs = sorted(p.name for p in (tmp_path / "plots").glob("*.png"))
    assert pngs == ["signals.png", "timing.png", "trajectory.png"], pngs


def test_a_robot_with_chips_on_a_bus_replays_its_recorded_transfers(tmp_path):
    """A replay answers the firmware's bus transfers from the recording (each bus's
    transfers in order, trace.jsonl), as it feeds back every other recorded input: the
    IMU, ranger and OLED robot replays to the same outputs (it stopped at the first
    transfer with ENODEV before)."""
    out = tmp_path / "run"
    rig = str(Path(__file__).resolve().parents[1] / "examples" / "oled_bot" / "rig.toml")
    done = mpy_fil("run", rig, "--duration", "4", "--out", str(out), "--no-plots")
    assert done.returncode == 0, f"mpy-fil run failed:\n{done.stdout}{done.stderr}"
    done = mpy_fil("replay", str(out), "--app", rig)
    assert done.returncode == 0 and "same outputs" in done.stdout, f"replay of {out}:\n{done.stdout}{done.stderr}"
