"""A rig file's ``[world]`` drawn as a picture (``kind = "line_course"``, docs/rig-file.md):
the picture's path is relative to the rig file, not to where the command runs; a missing
or unreadable picture is refused when the rig file is read (so by ``mpy-fil check``),
naming the rig file and the picture; the trace folder keeps the floor's picture (and the
manifest its hash) and the trajectory plots draw the path over it."""

import hashlib
import json
import os

import pytest
from PIL import Image

from host.artefacts.folder import load_trace
from host.cli import main
from host.core.errors import ConfigError
from host.report.movie import write_movie
from host.report.plots import trajectory_figure
from host.rig.config.rigfile import load_rig

RIG = """
name = "liner"

[firmware]
entry = "main.py"

[board.pins]
LINE = 26

[plant]
body = "differential"

[[plant.parts]]
kind = "dc_motor"
name = "motor_l"
drives = "left"

[[plant.parts]]
kind = "dc_motor"
name = "motor_r"
drives = "right"

[[plant.parts]]
kind = "line_sensor"
name = "line"

[wiring]
LINE = "line.0"

[world]
kind = "line_course"
picture = "floors/course.png"
mm_per_px = 5.0
start_pose = [0.25, 0.5, 0.0]
"""


def rig_folder(tmp_path, text=RIG, draw=True):
    folder = tmp_path / "bot"
    (folder / "floors").mkdir(parents=True)
    (folder / "main.py").write_text("import time\nfrom machine import ADC, Pin\n\nprint(ADC(Pin(26)).read_u16())\n")
    (folder / "rig.toml").write_text(text)
    if draw:  # 1.0 x 1.0 m, black right of x = 0.5 m
        image = Image.new("L", (200, 200), 255)
        image.paste(0, (100, 0, 200, 200))
        image.save(folder / "floors" / "course.png")
    return folder


def test_the_picture_is_found_beside_the_rig_file_from_any_folder(tmp_path, monkeypatch):
    folder = rig_folder(tmp_path)
    monkeypatch.chdir(tmp_path)  # (not the rig file's folder)
    plant = load_rig("bot/rig.toml").make_plant()
    assert plant.world.name == "line course 1 x 1 m" and plant.start_pose == (0.25, 0.5, 0.0)
    assert plant.output("line.0") == 6000, "white under the sensor"
    on_black = load_rig(folder / "rig.toml").make_plant(start_pose=[0.75, 0.5, 0.0])
    assert on_black.output("line.0") == 58000, "black under it"
    assert os.path.isabs(plant.body.options["world_options"]["picture"])


@pytest.mark.parametrize(
    ("draw", "picture", "why"),
    [
        (False, "floors/course.png", r"No such file or directory"),
        (True, "floors", r"Is a directory"),
        (True, "main.py", r"not a picture Pillow reads"),
    ],
)
def test_a_missing_or_unreadable_picture_names_the_rig_file_and_the_picture(tmp_path, capsys, draw, picture, why):
    folder = rig_folder(tmp_path, RIG.replace('"floors/course.png"', f'"{picture}"'), draw=draw)
    rig_file = folder / "rig.toml"
    message = rf"^{rig_file}: \[world\] picture: cannot read {folder / picture} \({why}"
    with pytest.raises(ConfigError, match=message):
        load_rig(rig_file)
    assert main(["check", str(rig_file)]) == 2
    err = capsys.readouterr().err
    assert str(rig_file) in err and f"cannot read {folder / picture}" in err, err


@pytest.mark.hil
def test_the_trace_folder_keeps_the_floor_and_the_trajectory_is_drawn_over_it(tmp_path, make_rig):
    folder = rig_folder(tmp_path)
    rig = make_rig(str(folder / "rig.toml"), record=True, allow_exit=True, artefacts=tmp_path / "run")
    rig.run_for(0.1)
    rig.stop()
    assert rig.console.split() == ["6000"], rig.console
    trace = load_trace(rig.artefacts)
    assert trace.header["world"]["floor"] == {"picture": "floor.png", "extent_m": [0.0, 1.0, 0.0, 1.0]}
    with Image.open(rig.artefacts / "floor.png") as floor:
        assert floor.size == (200, 200) and floor.getpixel((50, 100)) == 255 and floor.getpixel((150, 100)) == 0
        grey = hashlib.sha256(floor.tobytes()).hexdigest()
    manifest = json.loads((rig.artefacts / "manifest.json").read_text())
    assert manifest["plant"]["floor"] == {"sha256": grey, "size_px": [200, 200], "m_per_px": 0.005}, manifest["plant"]
    (image,) = trajectory_figure(trace).axes[0].images
    shown = image.get_array()
    assert list(image.get_extent()) == [0.0, 1.0, 0.0, 1.0] and shown.shape == (200, 200), "the floor under the path"
    assert shown[100, 50] == 255 and shown[100, 150] == 0, "white left, black right"
    movie = write_movie(trace, tmp_path / "trajectory.gif", frames=2)
    with Image.open(movie) as gif:
        dark = sum(n for n, value in gif.convert("L").getcolors() if value < 60) / (gif.width * gif.height)
    assert dark > 0.1, f"the floor's black half under the moving picture too: {dark:.0%} of it dark"
