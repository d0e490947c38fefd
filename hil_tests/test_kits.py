"""Robot kits (host/kits, docs/kits.md): ``mpy-fil init --kit`` writes a rig that
``mpy-fil check`` accepts with the kit's firmware and a test that passes; firmware in the
vendor library's style (hil_tests/firmware/kits/) drives 25 cm by the encoders, turns 90
degrees by the gyro and stops at a wall by the rangefinder, held to the plant's ground
truth in virtual time."""

import importlib.util
import json
import math
import re
import shutil
from pathlib import Path

import pytest
from PIL import Image

from host import kits
from host.artefacts.folder import load_trace
from host.artefacts.pictures import GAP_PX, SCALE, STRIP_SCALE
from host.cli import main
from host.report import part_views
from host.report.html import RigResult, _displays
from host.tests.test_oled import vlsb_rows

pytestmark = pytest.mark.hil
FIRMWARE = Path(__file__).parent / "firmware" / "kits"
WALL_Y_M = 2.0  # the room's north wall (room_h_m)
RANGER_X_M = 0.10  # the rangefinder's place ahead of the body's centre (the kits' rig.toml)


def cli(capsys, *args) -> tuple[int, str, str]:
    """mpy-fil in this process: (exit code, stdout, stderr)."""
    try:
        code = main([str(a) for a in args])
    except SystemExit as e:  # (argparse's error: exit 2)
        code = e.code
    out = capsys.readouterr()
    return code, out.out, out.err


def kit_folder(capsys, tmp_path: Path, kit: str, firmware: str) -> Path:
    """``init --kit`` into a fresh folder, then the kit's firmware of ours beside it."""
    folder = tmp_path / kit
    folder.mkdir()
    code, out, err = cli(capsys, "init", "--kit", kit, folder)
    assert code == 0, f"init --kit {kit}: {err}"
    assert sorted(p.name for p in folder.iterdir()) == ["rig.toml", f"test_{kit}.py"], out
    shutil.copytree(FIRMWARE / firmware, folder, dirs_exist_ok=True)
    return folder


def test_init_kit_refuses_to_overwrite_and_names_the_kits(capsys, tmp_path):
    folder = tmp_path / "k"
    folder.mkdir()
    (folder / "rig.toml").write_text("# mine\n")
    code, _, err = cli(capsys, "init", "--kit", "xrp_beta", folder)
    assert code == 2 and "rig.toml exists; nothing written" in err, err
    assert (folder / "rig.toml").read_text() == "# mine\n" and not (folder / "test_xrp_beta.py").exists()
    (folder / "rig.toml").unlink()
    (folder / "rig.toml").symlink_to(tmp_path / "elsewhere.toml")  # (dangling: writing through it would make it)
    code, _, err = cli(capsys, "init", "--kit", "xrp_beta", folder)
    assert code == 2 and "is a link" in err and not (tmp_path / "elsewhere.toml").exists(), err
    code, _, err = cli(capsys, "init", "--kit", "no_such_kit", folder)
    assert code == 2 and "no kit 'no_such_kit'" in err and "did you mean" not in err, err
    for typed, meant in (
        ("pololu", "pololu_3pi_2040"),
        ("3pi", "pololu_3pi_2040"),
        ("maker-pi", "cytron_maker_pi_rp2040"),
    ):
        code, _, err = cli(capsys, "init", "--kit", typed, folder)
        assert code == 2 and f"did you mean {meant}?" in err, (typed, err)
    # a new folder is made (the vendor's library goes in after, as docs/kits.md shows); one
    # whose parent is not there, or a file in its place, is named
    code, out, err = cli(capsys, "init", "--kit", "xrp_beta", tmp_path / "new")
    assert code == 0 and f"made {tmp_path / 'new'}/" in out, err
    assert sorted(p.name for p in (tmp_path / "new").iterdir()) == ["rig.toml", "test_xrp_beta.py"]
    code, _, err = cli(capsys, "init", "--kit", "xrp_beta", tmp_path / "nowhere" / "new")
    assert code == 2 and "no folder" in err and "nowhere" in err and not (tmp_path / "nowhere").exists(), err
    (tmp_path / "afile").write_text("")
    code, _, err = cli(capsys, "init", "--kit", "xrp_beta", tmp_path / "afile")
    assert code == 2 and "is not a folder" in err, err
    code, listing, _ = cli(capsys, "kits")
    for name, kit in kits.kits().items():
        assert f"{name:<14} {kit.title}" in listing and kit.sources, listing
        for what, where in kit.sources:
            assert f"  {what}: {where}" in listing


@pytest.mark.parametrize("kit", sorted(kits.kits()))
def test_init_kit_writes_a_test_that_passes(capsys, make_rig, monkeypatch, tmp_path, kit):
    """The test ``init --kit`` writes, run as pytest would run it (its own firmware, the
    kit's rig beside it), with compute free, as the rig it writes has it (no ``cpu``:
    docs/mcu-time.md, "Default"). Its figures are a free CPU's: the 3pi+ 2040's times each
    line sensor with ``time_pulse_us`` right after letting the pin go, within 10 us of the
    plant's 150 us; on an RP2040 (MPYFIL_CPU=rp2040@125MHz) it reads 109: the call itself is
    charged before the pulse is timed (a C call is 24.5 us in that model)."""
    monkeypatch.setenv("MPYFIL_CPU", "free")
    folder = tmp_path / kit
    folder.mkdir()
    code, _, err = cli(capsys, "init", "--kit", kit, folder)
    assert code == 0, err
    spec = importlib.util.spec_from_file_location(f"written_{kit}", folder / f"test_{kit}.py")
    written = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(written)
    tests = [getattr(written, n) for n in dir(written) if n.startswith("test_")]
    assert len(tests) == 1, dir(written)
    (tmp_path / "own").mkdir()
    tests[0](make_rig, tmp_path / "own")


@pytest.mark.parametrize("kit", ["xrp_beta", "xrp"])
def test_init_kit_rig_checks_clean_with_the_kits_firmware(capsys, tmp_path, kit):
    folder = kit_folder(capsys, tmp_path, kit, "xrp")
    code, _, err = cli(capsys, "check", folder / "rig.toml", "--strict")
    warnings = [line for line in err.splitlines() if line.startswith("check:")]
    if kit == "xrp":  # (the RGB LED's pin is Pin.board's, looked up at run time: only a run tells)
        assert warnings == [
            "check: the rig wires BOARD_NEOPIXEL = 37 (rgb.din), but the code never touches pin 37 "
            "(some pins are computed at run time: check -v lists them)"
        ], err
    else:
        assert code == 0 and not warnings, err


def said(rig, pattern: str) -> list[float]:
    found = rig.expect(pattern + r" (\S+)(?: (\S+))?")
    return [float(v) for v in found.groups() if v is not None]


@pytest.mark.parametrize("kit", ["xrp_beta", "xrp"])
def test_xrp_drives_turns_and_stops_at_the_wall_as_the_plant_says(capsys, make_rig, tmp_path, kit):
    folder = kit_folder(capsys, tmp_path, kit, "xrp")
    rig_file = folder / "rig.toml"
    text = rig_file.read_text().replace("start_pose = [0.5, 1.0, 0.0]", "start_pose = [1.0, 1.2, 0.0]")
    text = text.replace('name = "user_button"\n', 'name = "user_button"\npresses = [[0.2, 0.3]]\n')
    rig_file.write_text(text)
    rig = make_rig(str(rig_file), allow_exit=True)
    where = lambda: f"console:\n{rig.console}\nartefacts: {rig.artefacts}"  # noqa: E731
    (floor_l, floor_r) = said(rig, "floor")
    assert rig.t_us >= 300_000, f"started before the button was released (0.3 s); {where()}"
    assert floor_l == floor_r == pytest.approx(6000 / 65535, rel=1e-3), "the floor's reflectance (floor_u16 6000)"
    start = rig.truth()
    (straight_cm,) = said(rig, "straight_cm")
    after = rig.truth()
    moved_cm = math.hypot(after["x_m"] - start["x_m"], after["y_m"] - start["y_m"]) * 100
    assert abs(straight_cm - moved_cm) < 0.5, f"encoders said {straight_cm} cm, the body moved {moved_cm}; {where()}"
    assert abs(moved_cm - 25) < 0.5 and abs(after["theta_rad"]) < math.radians(1), (after, where())
    (turned_deg,) = said(rig, "turned_deg")
    turned = rig.truth()
    truly_deg = math.degrees(turned["theta_rad"] - after["theta_rad"])
    assert abs(truly_deg - 90) < 3 and abs(turned_deg - truly_deg) < 3, f"{turned_deg} vs {truly_deg}; {where()}"
    (wall_cm,) = said(rig, "wall_cm")
    end = rig.truth()
    ranger_y = end["y_m"] + RANGER_X_M * math.sin(end["theta_rad"])
    to_wall_cm = (WALL_Y_M - ranger_y) / math.sin(end["theta_rad"]) * 100
    assert abs(wall_cm - to_wall_cm) < 1.0, f"the rangefinder said {wall_cm} cm, the wall is {to_wall_cm}; {where()}"
    assert 8 < to_wall_cm <= 15 and end["touching"] == 0, (end, where())
    rig.expect("done")
    if kit == "xrp":  # the RP2350 controller's RGB LED: red once done
        assert rig.plant.output("rgb.led0") == 0x200000, where()


def test_3pi_drives_25_cm_by_its_encoders_and_turns_90_by_its_gyro(capsys, make_rig, tmp_path):
    """Pololu-style firmware (PWM slice 7 through mem32, PIO encoders, the LSM6DSO at 0x6B:
    the kitbot package as its library, in /lib) on the 3pi+ 2040 kit's rig, started by
    button B (BOOTSEL)."""
    folder = kit_folder(capsys, tmp_path, "pololu_3pi_2040", "pololu_3pi_2040")
    shutil.copytree(FIRMWARE.parent / "kitbot" / "lib", folder / "lib")
    rig_file = folder / "rig.toml"
    rig_file.write_text(
        rig_file.read_text().replace('name = "button_b"\n', 'name = "button_b"\npresses = [[0.2, 0.3]]\n')
    )
    rig = make_rig(str(rig_file), allow_exit=True)
    where = lambda: f"console:\n{rig.console}\nartefacts: {rig.artefacts}"  # noqa: E731
    start = rig.truth()
    (straight_mm,) = said(rig, "straight_mm")
    assert rig.t_us >= 300_000, f"started before button B was released (0.3 s); {where()}"
    after = rig.truth()
    moved_mm = math.hypot(after["x_m"] - start["x_m"], after["y_m"] - start["y_m"]) * 1000
    assert abs(straight_mm - moved_mm) < 5, f"encoders said {straight_mm} mm, the body moved {moved_mm}; {where()}"
    assert abs(moved_mm - 250) < 5 and abs(after["theta_rad"]) < math.radians(1), (after, where())
    (turned_deg,) = said(rig, "turned_deg")
    truly_deg = math.degrees(rig.truth()["theta_rad"] - after["theta_rad"])
    assert abs(truly_deg - 90) < 3 and abs(turned_deg - truly_deg) < 3, f"{turned_deg} vs {truly_deg}; {where()}"
    rig.expect("done")


def test_3pi_display_and_led_colours_are_in_the_report_as_the_firmware_drew_them(capsys, make_rig, tmp_path):
    """The 3pi+ 2040's SH1106 and six APA102 LEDs (sharing SPI0, a clock pin each) driven by
    firmware in Pololu's style (hil_tests/firmware/kits/pololu_3pi_show: three screens, a
    colour each): the trace folder's last picture and film strip are the firmware's frame
    buffers pixel for pixel, the report's HTML shows both, and the report's LED panel has
    each LED's colours in the order and at the instants the firmware set them."""
    folder = kit_folder(capsys, tmp_path, "pololu_3pi_2040", "pololu_3pi_show")
    shutil.copytree(FIRMWARE.parent / "kitbot" / "lib", folder / "lib")
    trace = tmp_path / "trace"
    rig = make_rig(str(folder / "rig.toml"), allow_exit=True, artefacts=trace, record=True)
    rig.expect("done")
    rig.stop()
    where = f"console:\n{rig.console}\nartefacts: {trace}"
    shown = [line.split()[-3:] for line in rig.console.splitlines() if " shown " in f" {line}"]
    assert [screen for screen, _ms, _hex in shown] == ["0", "1", "2"], where
    buffers = [vlsb_rows(bytes.fromhex(hexed), 128, 64) for _screen, _ms, hexed in shown]
    since_ms = [int(ms) - int(shown[0][1]) for _screen, ms, _hex in shown]  # (each screen's show after the first's)
    last = Image.open(trace / "display.png").convert("L")
    got = bytes(last.getpixel((x * SCALE, y * SCALE)) > 0 for y in range(64) for x in range(128))
    assert got == buffers[-1], f"display.png is the last frame buffer; {where}"
    header = json.loads((trace / "header.json").read_text())
    strip = header["displays"]["display"]
    assert len(strip["strip_t_us"]) == 3, f"the three screens held 300 ms each, not the pages between: {strip}"
    film = Image.open(trace / strip["strip"]).convert("L")
    tile = 128 * STRIP_SCALE + GAP_PX
    for i, want in enumerate(buffers):
        got = bytes(
            film.getpixel((i * tile + x * STRIP_SCALE, y * STRIP_SCALE)) > 0 for y in range(64) for x in range(128)
        )
        assert got == want, f"the film strip's picture {i} is screen {i}'s frame buffer; {where}"
        after_ms = (strip["strip_t_us"][i] - strip["strip_t_us"][0]) / 1000
        assert abs(after_ms - since_ms[i]) <= 30, f"{strip}: the firmware showed them {since_ms} ms after the first"
    html = "".join(_displays(RigResult("rig0", trace, header=header), trace))
    assert 'src="display.png"' in html and 'src="display.frames.png"' in html, html
    panels = part_views.part_panels(load_trace(trace))
    (leds,) = [p for p in panels if p.title.startswith("LED strips")]
    assert [line.label for line in leds.lines] == [f"rgb_leds.led{i}" for i in range(6)], where
    for line in leds.lines:
        assert list(line.values) == [0, 0xFF0000, 0x00FF00, 0x0000FF], f"{line.label}: {list(line.values)}; {where}"
        after_ms = [(t_s - line.t_s[1]) * 1000 for t_s in line.t_s[1:]]
        assert all(abs(a - s) <= 30 for a, s in zip(after_ms, since_ms, strict=True)), (
            f"{line.label} changed {after_ms} ms after its first colour, the firmware set them {since_ms}; {where}"
        )


@pytest.mark.parametrize(("heading_rad", "side"), [(-0.17, "left"), (0.17, "right")])
def test_3pi_bump_sensors_feel_the_wall_on_the_side_that_meets_it(
    capsys, make_rig, monkeypatch, tmp_path, heading_rad, side
):
    """The 3pi+ 2040's two bump sensors (QTR RC channels on GP17 and GP16, emitters on GP23)
    read as Pololu's library reads them (hil_tests/firmware/kits/pololu_3pi_bump, the
    thresholds calibrated standing): driven at the east wall 10 degrees off square, the
    flap on the side that meets it is pressed, and the robot stops at the contact.

    Compute free: here the CPU times the discharges itself (pololu_3pi_line's ir_sensors.py,
    Pin.value and ticks_us in a loop), each fall stamped with the clock read before the pass
    that saw it, and the thresholds are those of the flaps' 300 us to the microsecond. On an
    RP2040 (MPYFIL_CPU=rp2040@125MHz) a pass of that loop takes about 195 us (five C calls),
    and the released flaps read 180 (thresholds 252 and 288): the library's PIO timing is
    what holds there (test_kits_pio.py runs it on both)."""
    monkeypatch.setenv("MPYFIL_CPU", "free")
    folder = kit_folder(capsys, tmp_path, "pololu_3pi_2040", "pololu_3pi_bump")
    shutil.copytree(FIRMWARE.parent / "kitbot" / "lib", folder / "lib")
    shutil.copy(FIRMWARE / "pololu_3pi_line" / "ir_sensors.py", folder)
    rig_file = folder / "rig.toml"
    text = rig_file.read_text().replace('name = "button_b"\n', 'name = "button_b"\npresses = [[0.2, 0.3]]\n')
    rig_file.write_text(text.replace("start_pose = [0.5, 1.0, 0.0]", f"start_pose = [2.6, 1.0, {heading_rad}]"))
    rig = make_rig(str(rig_file), allow_exit=True)
    where = lambda: f"console:\n{rig.console}\nartefacts: {rig.artefacts}"  # noqa: E731
    low, high = rig.expect(r"thresholds \[(\d+), \d+\] \[(\d+), \d+\]").groups()
    assert (int(low), int(high)) == (420, 480), f"140 % and 160 % of the flaps' 300 us; {where()}"
    left, right = (int(v) for v in rig.expect(r"bumped (\d) (\d)").groups())
    truth = rig.truth()
    assert truth["contacts"], f"expected the body against the wall when a flap was pressed, got {truth}; {where()}"
    assert truth["bump_on_tape"] == [side == "left", side == "right"], f"the {side} flap pressed: {truth}; {where()}"
    assert (left, right) == (side == "left", side == "right"), f"the firmware felt the {side} flap; {where()}"
    gap_m = 3.0 - truth["x_m"] - 0.0485 * math.cos(heading_rad)  # (the east wall, the body's radius)
    assert abs(gap_m) < 0.01, f"stopped {gap_m * 1000:.1f} mm from the wall; {where()}"


def test_3pi_bump_sensors_released_together_read_alike_on_an_rp2040(capsys, make_rig, monkeypatch, tmp_path):
    """The two flaps' channels let go one after the other (Pin.init(Pin.IN) in a loop) and
    polled in one loop read alike with MCU time: each CFG is stamped after the compute
    before it, as an OUT is (_hil.configure). Stamped at the clock before that compute, the
    second channel's release came before the loop's start was read: it read 36 us where the
    first read 183 (thresholds [257, 50] [293, 57])."""
    monkeypatch.setenv("MPYFIL_CPU", "rp2040@125MHz")
    folder = kit_folder(capsys, tmp_path, "pololu_3pi_2040", "pololu_3pi_bump")
    shutil.copytree(FIRMWARE.parent / "kitbot" / "lib", folder / "lib")
    shutil.copy(FIRMWARE / "pololu_3pi_line" / "ir_sensors.py", folder)
    rig = make_rig(str(folder / "rig.toml"), allow_exit=True)
    found = rig.expect(r"thresholds \[(\d+), (\d+)\] \[(\d+), (\d+)\]").groups()
    low_l, low_r, high_l, high_r = (int(v) for v in found)
    assert (low_l, high_l) == (low_r, high_r), f"expected both flaps' thresholds alike, got {found}; {rig.console}"


@pytest.mark.parametrize(
    ("kit", "want"),
    [
        ("xrp_beta", "SparkFun XRP Controller (Beta) with RP2040 6 6 20 False 30 unknown named pin"),
        ("xrp", "SparkFun XRP Controller with RP2350 34 34 0 True 48 unknown named pin"),
    ],
)
def test_a_kit_boards_pins_by_its_own_names(capsys, make_rig, tmp_path, kit, want):
    """ports/rp2/boards/<BOARD>/pins.csv as the board's firmware has them: Pin("NAME") and
    the alternate names, Pin.board, Pin.cpu up to the chip's GPIO count, a Pin of a Pin."""
    folder = kit_folder(capsys, tmp_path, kit, "xrp")
    (folder / "main.py").write_text(
        """import sys
from machine import Pin

led = getattr(Pin.board, "BOARD_NEOPIXEL", None)
try:
    Pin("NO_SUCH_PIN")
except ValueError as e:
    unknown = str(e)
cpus = sum(1 for n in range(64) if hasattr(Pin.cpu, "GPIO%d" % n))
print("names", sys.implementation._machine, Pin("MOTOR_L_IN_1"), Pin("ML_IN_1"), Pin(Pin.board.RANGE_TRIGGER),
      led is not None and Pin(led, Pin.OUT) is led, cpus, unknown[:17])
"""
    )
    rig = make_rig(str(folder / "rig.toml"), allow_exit=True)
    line = rig.expect(r"names (.*)\n").group(1)
    got = re.sub(r"Pin\(GPIO(\d+)[^)]*\)", r"\1", line)
    assert got == want, f"console:\n{rig.console}"


def test_3pi_names_itself_as_its_board_definition_does(capsys, make_rig, tmp_path):
    """ports/rp2/boards/POLOLU_3PI_2040_ROBOT/mpconfigboard.h sets MICROPY_BANNER_MACHINE to
    the board's name, so sys.implementation._machine has no " with RP2040"; its pins by number
    up to the RP2040's 30 and the platform rp2 all the same."""
    folder = kit_folder(capsys, tmp_path, "pololu_3pi_2040", "pololu_3pi_led_button")
    (folder / "main.py").write_text(
        """import sys
from machine import Pin

cpus = sum(1 for n in range(64) if hasattr(Pin.cpu, "GPIO%d" % n))
print("names|%s|%s|%d" % (sys.platform, sys.implementation._machine, cpus))
"""
    )
    rig = make_rig(str(folder / "rig.toml"), allow_exit=True)
    line = rig.expect(r"names\|(.*)\n").group(1)
    want = "rp2|Pololu 3pi+ 2040 Robot|30"
    assert line == want, f"expected {want}, got {line!r}; console:\n{rig.console}"


def test_3pi_yellow_led_and_button_a_share_gp25_as_on_the_robot(capsys, make_rig, tmp_path):
    """The yellow LED driven as an output on GP25 (blink.py, gyro_turn.py: Pin(25, Pin.OUT))
    and button A read through the IO_BANK0 override on the same pin: the rig accepts the
    output, the plant's LED is lit while the pin drives low, and the button reads pressed
    (only) while it is, the LED's drive back after each read."""
    folder = kit_folder(capsys, tmp_path, "pololu_3pi_2040", "pololu_3pi_led_button")
    rig_file = folder / "rig.toml"
    text = rig_file.read_text()
    assert 'name = "button_a"\nled = "low"' in text, "the kit's button A carries the yellow LED"
    rig_file.write_text(text.replace('name = "button_a"\n', 'name = "button_a"\npresses = [[0.12, 0.22]]\n'))
    rig = make_rig(str(rig_file), allow_exit=True)
    where = lambda: f"console:\n{rig.console}\nartefacts: {rig.artefacts}"  # noqa: E731
    steps = []
    for _ in range(8):
        found = rig.expect(r"R step (\d+) (\d+) (\d) (\d)")
        step, ms, pressed, level = map(int, found.groups())
        lit = rig.truth()["button_a_led"]
        steps.append((step, ms, pressed, level, lit))
    for step, ms, pressed, level, lit in steps:
        on = step % 2 == 0
        assert level == (0 if on else 1) and lit == int(on), f"LED step {step}: {steps}; {where()}"
        assert pressed == int(120 <= ms < 220), f"button A at {ms} ms: {steps}; {where()}"
    assert [s[2] for s in steps] == [0, 0, 0, 1, 1, 0, 0, 0], f"pressed at 160 and 210 ms: {steps}; {where()}"


def test_3pi_button_c_shares_the_displays_dc_line_as_on_the_robot(capsys, make_rig, tmp_path):
    """Button C on GP0, the SH1106's DC line, read between display writes as the kit's
    library reads it (the pin an input with its pull-up for a moment, then driven low again):
    pressed only while the plant's button is, and the display's picture, drawn with the DC the
    same pin drives, is each frame buffer pixel for pixel."""
    folder = kit_folder(capsys, tmp_path, "pololu_3pi_2040", "pololu_3pi_button_c")
    shutil.copytree(FIRMWARE.parent / "kitbot" / "lib", folder / "lib")
    rig_file = folder / "rig.toml"
    text = rig_file.read_text()
    assert 'name = "button_c"\nshares = "display.dc"' in text, "the kit's button C is on the display's DC line"
    rig_file.write_text(text.replace('name = "button_c"\n', 'name = "button_c"\npresses = [[0.2, 0.7]]\n'))
    trace = tmp_path / "trace"
    rig = make_rig(str(rig_file), allow_exit=True, artefacts=trace, record=True)
    where = lambda: f"console:\n{rig.console}\nartefacts: {trace}"  # noqa: E731
    steps = []
    for _ in range(8):
        found = rig.expect(r"C step (\d+) (\d+) (\d) ([0-9a-f]+)")
        step, ms, pressed = map(int, found.groups()[:3])
        steps.append((step, ms, pressed, found.group(4)))
    rig.expect("done")
    rig.stop()
    pressed = [(ms, p) for _s, ms, p, _b in steps]
    assert all(p == int(200 <= ms < 700) for ms, p in pressed), f"pressed from 200 to 700 ms: {pressed}; {where()}"
    assert sum(p for _ms, p in pressed) >= 2, f"expected two reads inside the press: {pressed}; {where()}"
    last = Image.open(trace / "display.png").convert("L")
    got = bytes(last.getpixel((x * SCALE, y * SCALE)) > 0 for y in range(64) for x in range(128))
    assert got == vlsb_rows(bytes.fromhex(steps[-1][3]), 128, 64), f"display.png is the last frame buffer; {where()}"


def test_3pi_battery_level_on_gp26_reads_its_voltage_through_the_divider(capsys, make_rig, tmp_path):
    """The battery on GP26 (the down emitters' line), read as the kit's library reads it:
    its 4.8 V through the 1/11 divider, to the ADC's step (12 bits: 8.9 mV of battery),
    before and after the pin has driven the emitters on and let them go."""
    folder = kit_folder(capsys, tmp_path, "pololu_3pi_2040", "pololu_3pi_battery")
    rig = make_rig(str(folder / "rig.toml"), allow_exit=True)
    rig.expect("done")
    where = f"console:\n{rig.console}\nartefacts: {rig.artefacts}"
    readings = [int(v) for v in re.findall(r"vbat (\d+)", rig.console)]
    want_mv = rig.truth()["battery_v"] * 1000
    assert len(readings) == 2 and all(abs(mv - want_mv) <= 9 for mv in readings), (
        f"{readings} mV, want {want_mv}; {where}"
    )
    assert "emitters 1" in rig.console, where


def test_3pi_yellow_led_dimmed_by_a_pwm_on_gp25_beside_button_a(capsys, make_rig, tmp_path):
    """Pololu's splash loader fades the yellow LED with PWM(YellowLED().pin) on GP25, the line
    button A shares: the rig takes the PWM (it was refused as a second driver of the button's
    line), the LED is lit while the PWM holds the line low most of the time, and the pin
    drives it again after the PWM's deinit."""
    folder = kit_folder(capsys, tmp_path, "pololu_3pi_2040", "pololu_3pi_led_pwm")
    rig = make_rig(str(folder / "rig.toml"), allow_exit=True)
    where = lambda: f"console:\n{rig.console}\nartefacts: {rig.artefacts}"  # noqa: E731
    lit = []
    for expected in (r"R pwm 0 60000", r"R pwm 1 5000", r"R pin 1"):
        rig.expect(expected)
        lit.append(rig.truth()["button_a_led"])
    assert lit == [0, 1, 0], f"expected the LED off at 92 % duty, lit at 8 %, off driven high: {lit}; {where()}"
