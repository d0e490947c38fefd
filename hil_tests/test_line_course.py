"""A kit follows a line course drawn as a picture (the ``line_course`` world, docs/rig-file.md):
the test draws a rounded-rectangle loop of black tape on white as a PNG, puts it under the
SparkFun XRP kit's rig (``mpy-fil init --kit xrp``), and the XRP's line follower
(hil_tests/firmware/kits/xrp_line: the two reflectance channels, PD on their difference,
in XRPLib's style) drives a lap in virtual time. The plant's pose is the judge: the lap's
length, the return to the start, and the sensor bar never further from the line's centre
than the margin. The kitbot (QTR RC channels, Pololu's style) and the Pololu 3pi+ 2040 kit
(its five QTR RC line sensors) take the course's first corner the same way (a lap of
either costs about its own time in wall time: their reads are many round trips); ``make
hil`` runs the 3pi+'s whole lap, and the Kitronik buggy's on Kitronik's own library."""

import math
import shutil
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from host.cli import main
from host.core.drivers import DriverMissing, driver_folder

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
POLL_PASS_US = 60  # a pass of a polling loop over five pins: the clock and five pin reads, 10 us each while spinning
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


class SensorPath:
    """The sensor bar's centre (``ahead_m`` before the wheels' axle) on the plant's true pose,
    sampled each time it is called (``run_until``'s look every 10 ms): its length, its
    distance from the course's line."""

    def __init__(self, rig, ahead_m: float):
        self.rig, self.ahead_m = rig, ahead_m
        self.t0_us = rig.t_us
        self.points = []  # (t_us, x_m, y_m, heading_rad)
        self.length_m = 0.0

    def sample(self) -> tuple:
        truth = self.rig.truth()
        th = truth["theta_rad"]
        point = (
            self.rig.t_us,
            truth["x_m"] + self.ahead_m * math.cos(th),
            truth["y_m"] + self.ahead_m * math.sin(th),
            th,
        )
        if self.points:
            self.length_m += math.dist(self.points[-1][1:3], point[1:3])
        self.points.append(point)
        return point

    def worst_off_line(self) -> tuple[float, tuple]:
        """(The greatest distance from the line's centre, where and when it was.)"""
        errors = off_line_m(np.array([p[1] for p in self.points]), np.array([p[2] for p in self.points]))
        worst = int(np.argmax(errors))
        return float(errors[worst]), self.points[worst]

    def lap(self, where, timeout_s: float, rel: float = 0.03, heading_deg: float = 10.0) -> str:
        """Run until the bar has gone most of the way round and is back across the start;
        then hold the lap: its length within ``rel`` of the loop's, within the margin of the
        line all along, back on the start line heading along it (within ``heading_deg``),
        never lost. ``where``: the failure messages' tail (a callable). The lap in a line
        (the report's result)."""
        rig, start_x = self.rig, START[0] + self.ahead_m

        def lapped():
            _, x, y, _ = self.sample()
            return self.length_m > 0.9 * LAP_M and x >= start_x and y < CENTRE_M[1]  # back across the start

        rig.run_until(lapped, timeout_s=timeout_s)
        _, x, y, th = self.points[-1]
        off_m = self.check_on_line(where())
        lap_s = (rig.t_us - self.t0_us) / 1e6
        result = f"lap {lap_s:.2f} s, {self.length_m:.3f} m of {LAP_M:.3f}, at most {off_m * 1000:.1f} mm off the line"
        print(result)
        assert "lost" not in rig.console, f"the firmware lost the line; {where()}"
        assert self.length_m == pytest.approx(LAP_M, rel=rel), f"the sensors went {self.length_m:.3f} m; {where()}"
        assert abs(y - START[1]) <= MARGIN_M and abs(math.remainder(th, math.tau)) < math.radians(heading_deg), (
            f"back at the start line ({start_x:.2f}, {START[1]:.2f}) m heading 0: at ({x:.3f}, {y:.3f}) "
            f"heading {math.degrees(th):.1f} deg; {where()}"
        )
        return result

    def check_on_line(self, where: str) -> float:
        off_m, (t_us, x, y, _) = self.worst_off_line()
        assert off_m <= MARGIN_M, (
            f"expected the sensor bar within {MARGIN_M * 1000:.0f} mm of the line's centre, got {off_m * 1000:.1f} mm "
            f"at ({x:.3f}, {y:.3f}) m, {(t_us - self.t0_us) / 1e6:.2f} s in; {where}"
        )
        return off_m


def on_the_course(rig_file: Path, changes: dict) -> Path:
    """The rig file with the course as its world: ``changes`` (text -> its replacement, each
    there) made, the room and the start pose taken out."""
    text = rig_file.read_text()
    room = {"room_w_m = 3.0\n": "", "room_h_m = 2.0\n": "", "start_pose = [0.5, 1.0, 0.0]\n": ""}
    for old, new in {**room, **changes}.items():
        assert old in text, f"{rig_file} changed: no {old!r}"
        text = text.replace(old, new)
    draw_course(rig_file.parent / "course.png")
    rig_file.write_text(
        text
        + f"""
[world]
kind = "line_course"
picture = "course.png"
mm_per_px = {MM_PER_PX}
start_pose = {list(START)}
"""
    )
    return rig_file


def xrp_on_the_course(capsys, tmp_path: Path) -> Path:
    """``init --kit xrp``, our XRP line follower beside it, the course under it; the rig file."""
    folder = tmp_path / "xrp"
    folder.mkdir()
    code = main(["init", "--kit", "xrp", str(folder)])
    assert code == 0, capsys.readouterr().err
    shutil.copytree(FIRMWARE / "xrp" / "xrpkit", folder / "xrpkit")
    shutil.copy(FIRMWARE / "xrp_line" / "main.py", folder / "main.py")
    pressed = {'name = "user_button"\n': 'name = "user_button"\npresses = [[0.1, 0.2]]\n'}
    return on_the_course(folder / "rig.toml", pressed)


def test_xrp_follows_a_drawn_line_course_for_a_lap_within_its_margin(capsys, make_rig, tmp_path, record_property):
    rig = make_rig(str(xrp_on_the_course(capsys, tmp_path)))
    where = lambda: f"console:\n{rig.console}\nartefacts: {rig.artefacts}"  # noqa: E731
    (left, right) = (float(v) for v in rig.expect(r"start (\S+) (\S+)").groups())
    assert min(left, right) > 0.5, f"both channels over the tape at the start: {left}, {right}; {where()}"
    path = SensorPath(rig, ahead_m=0.08)  # the reflectance board (the kit's rig.toml)
    record_property("result", path.lap(where, timeout_s=40))


def test_kitbot_takes_the_courses_first_corner_by_its_qtr_channels(make_rig, tmp_path):
    """The QTR RC channels in the loop over the picture: driven high, let go, timed (the
    discharge by the picture's darkness under each), through the first quarter circle."""
    folder = tmp_path / "kitbot"
    shutil.copytree(FIRMWARE.parent / "kitbot", folder)
    shutil.copy(FIRMWARE.parent / "kitbot_line" / "main.py", folder / "main.py")
    tape = "tape = [[0.62, 0.5], [0.62, 1.5]]     # a dark line across its path\n"
    rig = make_rig(str(on_the_course(folder / "rig.toml", {tape: ""})))
    where = lambda: f"console:\n{rig.console}\nartefacts: {rig.artefacts}"  # noqa: E731
    assert rig.expect(r"calibrated (\S+) (\S+)").groups() == ("120", "700"), f"white_us, black_us; {where()}"
    path = SensorPath(rig, ahead_m=0.04)  # the QTR array (kitbot's rig.toml)
    corner_end_y = CENTRE_M[1] - HALF_M[1] + CORNER_M  # where the right straight begins

    def cornered():
        _, _, y, th = path.sample()
        return y > corner_end_y + 0.05 and th > math.radians(80)

    rig.run_until(cornered, timeout_s=10)
    off_m = path.check_on_line(where())
    print(f"corner {(rig.t_us - path.t0_us) / 1e6:.2f} s, at most {off_m * 1000:.1f} mm off the line")
    assert "lost" not in rig.console, f"the firmware lost the line; {where()}"
    assert rig.truth()["line_on_tape"][1], f"the middle channel over the line; {where()}"


def pololu_3pi_on_the_course(capsys, make_rig, tmp_path: Path):
    """``init --kit pololu_3pi_2040``, our Pololu-style line follower beside it, the course
    under it, button B pressed: the rig, its first read held to the plant's discharge times."""
    folder = tmp_path / "pololu_3pi_2040"
    folder.mkdir()
    assert main(["init", "--kit", "pololu_3pi_2040", str(folder)]) == 0, capsys.readouterr().err
    shutil.copytree(FIRMWARE.parent / "kitbot" / "lib", folder / "lib")
    shutil.copytree(FIRMWARE / "pololu_3pi_line", folder, dirs_exist_ok=True)
    pressed = {'name = "button_b"\n': 'name = "button_b"\npresses = [[0.1, 0.2]]\n'}
    rig = make_rig(str(on_the_course(folder / "rig.toml", pressed)))
    where = lambda: f"console:\n{rig.console}\nartefacts: {rig.artefacts}"  # noqa: E731
    start = [int(v) for v in rig.expect(r"start \[([^]]*)\]").group(1).split(",")]
    truth = rig.truth()
    assert truth["line_on_tape"] == [False, False, True, False, False], f"the middle sensor on the tape; {where()}"
    for got, true in zip(start, truth["line_discharge_us"]):  # (data[0] the left: line.0, GP22)
        assert abs(got - true) <= POLL_PASS_US, (
            f"expected each read within a polling pass ({POLL_PASS_US} us) of its discharge time, read {start}, "
            f"discharged {truth['line_discharge_us']} us; {where()}"
        )
    return rig


def test_3pi_takes_the_courses_first_corner_by_its_five_qtr_line_sensors(capsys, make_rig, tmp_path):
    """The 3pi+ 2040 kit's rig (``init --kit pololu_3pi_2040``: five QTR RC line sensors on
    GP18..GP22, their emitters on GP26) on the course, with a line follower in the style of
    Pololu's (hil_tests/firmware/kits/pololu_3pi_line: the sensors read as the library reads
    them, emitters on, charged, let go together and timed; calibrated by a sweep over the
    line; PD on the line's position under the five), through the first quarter circle."""
    rig = pololu_3pi_on_the_course(capsys, make_rig, tmp_path)
    where = lambda: f"console:\n{rig.console}\nartefacts: {rig.artefacts}"  # noqa: E731
    rig.expect(r"calibrated")
    path = SensorPath(rig, ahead_m=0.035)  # the line sensors (the kit's rig.toml)
    corner_end_y = CENTRE_M[1] - HALF_M[1] + CORNER_M

    def cornered():
        _, _, y, th = path.sample()
        return y > corner_end_y + 0.05 and th > math.radians(80)

    rig.run_until(cornered, timeout_s=10)
    off_m = path.check_on_line(where())
    print(f"corner {(rig.t_us - path.t0_us) / 1e6:.2f} s, at most {off_m * 1000:.1f} mm off the line")
    assert "lost" not in rig.console, f"the firmware lost the line; {where()}"
    truth = rig.truth()
    assert truth["line_on_tape"][2], f"the middle sensor over the line; {where()}"
    assert truth["rgb_leds_lit"] == 6 and truth["rgb_leds_faults"] == 0, f"six LEDs lit green: {truth}; {where()}"


@pytest.mark.skipif(
    "not config.getoption('--hil-report')", reason="make hil runs the 3pi+'s whole lap (about real time)"
)
def test_3pi_follows_the_drawn_course_for_a_lap_by_its_five_qtr_line_sensors(
    capsys, make_rig, tmp_path, record_property
):
    """The corner test's robot on for a whole lap: once round (the line sensors' path within
    3 % of the loop's length), back across the start on its line, never more than the
    margin off it, never lost."""
    rig = pololu_3pi_on_the_course(capsys, make_rig, tmp_path)
    where = lambda: f"console:\n{rig.console}\nartefacts: {rig.artefacts}"  # noqa: E731
    rig.expect(r"calibrated")
    path = SensorPath(rig, ahead_m=0.035)
    record_property("result", path.lap(where, timeout_s=40))


@pytest.mark.skipif(
    "not config.getoption('--hil-report')", reason="make hil runs the buggy's whole lap (about real time)"
)
def test_kitronik_buggy_follows_the_drawn_course_for_a_lap_on_kitronik_s_own_library(
    capsys, make_rig, tmp_path, record_property
):
    """The ``kitronik_buggy`` kit's rig on the course, Kitronik's own library (pinned,
    fetched by ``make setup``) unchanged beside a line follower in the style of their
    Basic3SensorLineFollow.py (hil_tests/firmware/kits/kitronik_line: the centre sensor on
    the line drives ahead, else a motor reverses towards the darker side), the button
    pressed by the test: once round and back across the start on its line, within the
    margin, never lost. The path is longer than the loop by the bang-bang follower's
    zigzag (their demo's own way): within 5 %."""
    try:
        library = driver_folder("kitronikpicoautonomousroboticsplatform") / "PicoAutonomousRobotics.py"
    except DriverMissing as e:
        pytest.skip(str(e))
    folder = tmp_path / "kitronik_buggy"
    folder.mkdir()
    assert main(["init", "--kit", "kitronik_buggy", str(folder)]) == 0, capsys.readouterr().err
    shutil.copy(library, folder)
    shutil.copy(FIRMWARE / "kitronik_line" / "main.py", folder / "main.py")
    pressed = {'name = "button"\n': 'name = "button"\npresses = [[0.1, 0.2]]\n'}
    rig = make_rig(str(on_the_course(folder / "rig.toml", pressed)))
    where = lambda: f"console:\n{rig.console}\nartefacts: {rig.artefacts}"  # noqa: E731
    left, centre, right = (int(v) for v in rig.expect(r"start (\d+) (\d+) (\d+)").groups())
    assert centre > 30000 > max(left, right), f"the centre sensor alone over the line at the start; {where()}"
    path = SensorPath(rig, ahead_m=0.07)  # the line following board (the kit's rig.toml)
    record_property("result", path.lap(where, timeout_s=60, rel=0.05, heading_deg=20))
