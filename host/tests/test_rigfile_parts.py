"""Rig files that describe the plant as a body and parts (``[plant] body = ...`` and
``[[plant.parts]]``, docs/parts.md): checked whole, refused by name, worlds give body
options, and `mpy-fil check` / `mpy-fil list` speak of them."""

import subprocess
import sys

import pytest

from host.core.errors import ConfigError
from host.core.paths import REPO
from host.rig.config.rigfile import load_rig

EXAMPLE = REPO / "examples" / "two_sonar_bot" / "rig.toml"


def copy_rig(tmp_path, old: str = "", new: str = ""):
    folder = tmp_path / "bot"
    folder.mkdir()
    (folder / "main.py").write_text((EXAMPLE.parent / "main.py").read_text())
    text = EXAMPLE.read_text()
    assert old in text
    (folder / "rig.toml").write_text(text.replace(old, new))
    return folder / "rig.toml"


def test_the_example_rig_builds_its_plant_with_both_rangers_and_its_worlds(tmp_path):
    app = load_rig(copy_rig(tmp_path))
    plant = app.make_plant()
    assert {"sonar_front.echo", "sonar_rear.echo", "start.out", "enc_r.b"} <= set(plant.outputs)
    assert set(app.worlds) == {"box-ahead", "wall-ahead"}
    assert app.make_plant(**app.worlds["wall-ahead"]).world.name == "room"
    with pytest.raises(ValueError, match=r"\[plant\] room_w_m: expected"):
        app.make_plant(room_w_m=-3)


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        (
            'name = "sonar_rear"',
            'name = "sonar_rear"\nnoise_sd_m = 20.0',
            r"#6 \(sonar_rear\) noise_sd_m: expected a number",
        ),
        (
            'drives = "right"',
            'drives = "front"',
            r"#2 \(motor_r\) drives: expected one of left, right, rear, got 'front'",
        ),
        ('kind = "probe"', 'kind = "lamp"', r"#8 kind: expected one of (.*, )?analog_ranger"),
        (
            "[worlds.wall-ahead]\nobstacles = []",
            "[worlds.wall-ahead]\nobstacles = 3",
            r"\[worlds.wall-ahead\]: \[plant\] obstacles",
        ),
        ('BUTTON = "start.out"', 'BUTTON = "start.in"', r"\[wiring\] BUTTON: the plant has no signal 'start.in'"),
    ],
)
def test_a_bad_part_is_refused_naming_the_file_the_table_and_the_field(tmp_path, old, new, message):
    path = copy_rig(tmp_path, old, new)
    with pytest.raises(ConfigError, match=message) as caught:
        load_rig(path)
    assert str(path) in str(caught.value)


def mpy_fil(*args):
    return subprocess.run(
        [sys.executable, "-m", "host.cli", *args], cwd=REPO, capture_output=True, text=True, timeout=60
    )


def test_mpy_fil_check_names_the_body_and_parts_and_a_bad_option_exits_2_in_one_line(tmp_path):
    done = mpy_fil("check", str(EXAMPLE))
    assert done.returncode == 0, done.stderr
    assert "plant: differential body with dc_motor motor_l" in done.stdout
    assert "sonar_rear.echo (level)" in done.stdout
    path = copy_rig(tmp_path, 'drives = "left"', 'drives = "left"\ntime_constant_ms = -5')
    done = mpy_fil("check", str(path))
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert done.stderr.strip().count("\n") == 0
    assert "[[plant.parts]] #1 (motor_l) time_constant_ms: expected a number of milliseconds" in done.stderr


def test_mpy_fil_list_lists_the_catalogue():
    done = mpy_fil("list")
    assert done.returncode == 0, done.stderr
    assert "bodies ([plant] body; docs/parts.md)" in done.stdout and "parts ([[plant.parts]] kind" in done.stdout
    assert "judges ([campaign] judge" in done.stdout and "  duct_branch " in done.stdout, "the catalogue's judges"
    assert "ir_distance" in done.stdout and "time_constant_ms=40.0" in done.stdout


@pytest.mark.parametrize(
    ("report", "message"),
    [
        ('[report]\nviews = ["Rover View"]', r"\[report\] views\[0\]: expected a view's name"),
        ('[report]\nsee = ["rover"]', r"\[report\] see: unknown key"),
        ('[report.pose_line]\ntag = "pose"', r"\[report.pose_line\]: missing columns"),
    ],
)
def test_a_bad_report_table_is_refused_naming_its_field(tmp_path, report, message):
    path = copy_rig(tmp_path, "[worlds.box-ahead]", report + "\n\n[worlds.box-ahead]")
    with pytest.raises(ConfigError, match=message):
        load_rig(path)
