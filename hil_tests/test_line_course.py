"""A kit follows a line course drawn as a picture (the ``line_course`` world, docs/parts.md):
the test draws a rounded-rectangle loop of black tape on white as a PNG, puts it under the
SparkFun XRP kit's rig (``mpy-fil init --kit xrp``), and the XRP's line follower
(hil_tests/firmware/kits/xrp_line: the two reflectance channels, PD on their difference,
in XRPLib's style) drives a lap in virtual time. The plant's pose is the judge: the lap's
length, the return to the start, and the sensor bar never further from the line's centre
than the margin."""

import math
import shutil
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from host.cli import main

pytestmark = pytest.mark.hil
FIRMWARE = Path(__file__).parent / "firmware" / "kits"

MM_PER_PX = 2.0
PICTURE_M = (1.4, 1.0)  # the picture's width and height: 700 x 500 pixels
CENTRE_M = (0.7, 0.5)  # the loop's centre line: a rounded rectangle 1.0 x 0.7 m
HALF_M = (0.5, 0.35)
CORNER_M = 0.2  # its corners' radius
TAPE_M = 0.019  # 3/4 inch electrical tape
LAP_M = 4 * (HALF_M[0] - CORNER_M) + 4 * (HALF_M[1] - CORNER_M) + 2 * math.pi * CORNER_M  # 3.057 m
START = (0.5, CENTRE_M[1] - HALF_M[1], 0.0)  # on the bottom straight, heading along it (anticlockwise)
SENSOR_X_M = 0.08  # the reflectance board ahead of the wheels' axle (the kit's rig.toml)
MARGIN_M = 0.012  # the sensor bar's centre stays this close to the line's centre (the tape is 9.5 mm each side)


def off_line_m(x, y):
    """Distance from the course's centre line (numbers or numpy arrays)."""
    qx = np.abs(x - CENTRE_M[0]) - (HALF_M[0] - CORNER_M)
    qy = np.abs(y - CENTRE_M[1]) - (HALF_M[1] - CORNER_M)
    signed = np.hypot(np.maximum(qx, 0), np.maximum(qy, 0)) + np.minimum(np.maximum(qx, qy), 0) - CORNER_M
    return np.abs(signed)


def draw_course(path: Path) -> None:
    """The loop as a PNG: black tape on white, its edges anti-aliased over a pixel."""
    px_m = MM_PER_PX / 1000
    w, h = round(PICTURE_M[0] / px_m), round(PICTURE_M[1] / px_m)
    x = (np.arange(w) + 0.5) * px_m
    y = (h - np.arange(h) - 0.5) * px_m  # (rows from the top)
    dark = np.clip(0.5 - (off_line_m(x[None, :], y[:, None]) - TAPE_M / 2) / px_m, 0, 1)
    Image.fromarray(np.round(255 * (1 - dark)).astype(np.uint8), "L").save(path)


def xrp_on_the_course(capsys, tmp_path: Path) -> Path:
    """``init --kit xrp``, our XRP line follower beside it, the course under it; the rig file."""
    folder = tmp_path / "xrp"
    folder.mkdir()
    code = main(["init", "--kit", "xrp", str(folder)])
    assert code == 0, capsys.readouterr().err
    shutil.copytree(FIRMWARE / "xrp" / "xrpkit", folder / "xrpkit")
    shutil.copy(FIRMWARE / "xrp_line" / "main.py", folder / "main.py")
    draw_course(folder / "course.png")
    rig_file = folder / "rig.toml"
    text = rig_file.read_text()
    for line in ("room_w_m = 3.0\n", "room_h_m = 2.0\n", "start_pose = [0.5, 1.0, 0.0]\n"):
        assert line in text, f"the xrp kit's rig.toml changed: no {line!r}"
        text = text.replace(line, "")
    text = text.replace('name = "user_button"\n', 'name = "user_button"\npresses = [[0.1, 0.2]]\n')
    text += f"""
[world]
kind = "line_course"
picture = "course.png"
mm_per_px = {MM_PER_PX}
start_pose = {list(START)}
"""
    rig_file.write_text(text)
    return rig_file


def test_xrp_follows_a_drawn_line_course_for_a_lap_within_its_margin(capsys, make_rig, tmp_path):
    rig = make_rig(str(xrp_on_the_course(capsys, tmp_path)))
    where = lambda: f"console:\n{rig.console}\nartefacts: {rig.artefacts}"  # noqa: E731
    (left, right) = (float(v) for v in rig.expect(r"start (\S+) (\S+)").groups())
    assert min(left, right) > 0.5, f"both channels over the tape at the start: {left}, {right}; {where()}"
    t0_us = rig.t_us
    path = []  # (t_us, the sensor bar's centre x, y, heading)

    def lapped():
        truth = rig.truth()
        th = truth["theta_rad"]
        x, y = truth["x_m"] + SENSOR_X_M * math.cos(th), truth["y_m"] + SENSOR_X_M * math.sin(th)
        path.append((rig.t_us, x, y, th))
        travelled = sum(math.dist(a[1:3], b[1:3]) for a, b in zip(path[-2:], path[-1:]))
        lapped.m += travelled
        back = lapped.m > 0.9 * LAP_M and x >= START[0] + SENSOR_X_M and y < CENTRE_M[1]
        return back

    lapped.m = 0.0
    rig.run_until(lapped, timeout_s=40)
    lap_s = (rig.t_us - t0_us) / 1e6
    t_us, x, y, th = path[-1]
    errors = off_line_m(np.array([p[1] for p in path]), np.array([p[2] for p in path]))
    worst = int(np.argmax(errors))
    print(f"lap {lap_s:.2f} s, {lapped.m:.3f} m of {LAP_M:.3f}, max off the line {errors[worst] * 1000:.1f} mm")
    assert "lost" not in rig.console, f"the firmware lost the line; {where()}"
    assert lapped.m == pytest.approx(LAP_M, rel=0.03), f"the sensor bar went {lapped.m:.3f} m; {where()}"
    assert errors[worst] <= MARGIN_M, (
        f"expected the sensor bar within {MARGIN_M * 1000:.0f} mm of the line's centre all lap, got "
        f"{errors[worst] * 1000:.1f} mm at ({path[worst][1]:.3f}, {path[worst][2]:.3f}) m, "
        f"{(path[worst][0] - t0_us) / 1e6:.2f} s in; {where()}"
    )
    assert abs(y - START[1]) <= MARGIN_M and abs(math.remainder(th, math.tau)) < math.radians(10), (
        f"back at the start line ({START[0] + SENSOR_X_M:.2f}, {START[1]:.2f}) m heading 0: at ({x:.3f}, {y:.3f}) "
        f"heading {math.degrees(th):.1f} deg; {where()}"
    )
