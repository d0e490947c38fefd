"""What ``mpy-fil check`` refuses that no one field shows wrong alone (host/rig/config/rigrules.py),
every unknown name with the whole list and the nearest, nesting bombs named where they
are, and the firmware's control characters escaped in everything the harness prints
(kept raw in ``console.log``)."""

import json
import re
import shutil
import subprocess
import sys

import pytest

from host import cli
from host.core.errors import ConfigError, FirmwareError
from host.core.nesting import loads_json, too_deep
from host.core.paths import REPO
from host.core.printable import printable
from host.rig.config.boardfile import apps_of
from host.rig.config.rigfile import load_rig
from host.rig.config.wokwi.diagram import read_diagram
from host.rig.loop.waits import ExpectTimeout
from host.scenario.scenario import ScenarioError, load_scenario

OLED_BOT = REPO / "examples" / "oled_bot"
BASE = (OLED_BOT / "rig.toml").read_text()
OLED = 'name = "oled"                           # 0x3C on i2c0: oled.png and oled.gif in the trace folder\nbus = "i2c0"'
IMU = 'bus = "i2c0"\n\n[[plant.parts]]\nkind = "vl53l0x"'


def rig_with(tmp_path, old: str, new: str):
    assert old in BASE, old
    folder = tmp_path / "bot"
    folder.mkdir(exist_ok=True)
    (folder / "main.py").write_text("")
    path = folder / "rig.toml"
    path.write_text(BASE.replace(old, new, 1))
    return path


POSE_LINE = """[report.pose_line]
tag = "pose"
columns = ["t", "x", "y", "h"]
m_per_unit = 0.01
rad_per_unit = 0.01
probe = "probe:quantm"
what = "odometry"
"""
BAD_RIGS = [  # (what is changed, into what, the field named, words the message must hold)
    (IMU, IMU.replace('"i2c0"', '"i2c:16,17"'), "[[plant.parts]] #3 (imu) bus", ["PWMA = 16", "motor_l.pwm"]),
    (OLED, 'name = "oled"\nbus = "spi:5,5,5"\nspi = true', "[[plant.parts]] #5 (oled) bus", ["pin 5 is twice"]),
    (IMU, IMU.replace('"i2c0"', '"i2c:GPIO16,4"'), "[[plant.parts]] #3 (imu) bus", ["GPIO16", "PWMA = 16"]),
    (OLED, 'name = "oled"\nbus = "spi:5,GP5,"\nspi = true', "[[plant.parts]] #5 (oled) bus", ["pin GP5 is twice"]),
    (
        "start_pose = [1.0, 0.5, 0.0]",
        "start_pose = [1.0, 0.5, 0.0]\nobstacles = [[1.1, 0.5, 0.1, 0.4]]",
        "[plant] start_pose",
        ["mm into a wall or an obstacle"],
    ),
    (IMU, IMU.replace('"i2c0"', '"i2c:99,98"'), "[[plant.parts]] #3 (imu) bus", ["from 0 to 48", "esp32"]),
    (OLED, 'name = "oled"\nbus = "i2c9"', "[[plant.parts]] #5 (oled) bus", ["i2c0, i2c1", "did you mean"]),
    (OLED, 'name = "oled"\nbus = "spi0"\nspi = true', "[[plant.parts]] #5 (oled) bus", ["spi1, spi2"]),
    (IMU, IMU.replace('"i2c0"', '"dht:16"'), "[[plant.parts]] #3 (imu)", []),  # (a DHT's line: no IMU's bus)
    ('PWMB = "motor_r.pwm"', 'PWMB = "motor_l.pwm"', "[wiring] PWMB", ["motor_l.pwm is wired to PWMA"]),
    ('BIN2 = "motor_r.in2"', 'BIN2 = "probe:../../x"', "[wiring] BIN2", ["'../../x'"]),
    ('BIN2 = "motor_r.in2"', 'BIN2 = "probe:a.b"', "[wiring] BIN2", ["no '.'"]),
    ('PWMA = "motor_l.pwm"', 'PWMA = "motor_l.pwn"', "[wiring] PWMA", ["did you mean 'motor_l.pwm'"]),
    ('PWMA = "motor_l.pwm"', 'PWM_A = "motor_l.pwm"', "[wiring] PWM_A", ["did you mean 'PWMA'"]),
    ("address = 0x6A", "address = 300", "[budgets.gyro_read] address", ["0x6a (imu)"]),
    ("address = 0x6A", "address = 0x6B", "[budgets.gyro_read] address", ["would match no transfer"]),
    ("register = 0x1E", "register = -1", "[budgets.ranging] register", ["0 to 255"]),
    ("register = 0x1E", "register = 256", "[budgets.ranging] register", ["0 to 255"]),
    ('source = "i2c0"\naddress = 0x6A', 'source = "i2c1"\naddress = 0x6A', "[budgets.gyro_read] source", ["i2c0"]),
    ('name = "imu"', 'name = "imu.x"', "[[plant.parts]] #3 name", ["no '.'"]),
    ('family = "esp32"', 'family = "esp32"\nalso = ["rpi_pic"]', "[board] also", ["did you mean 'rpi_pico'"]),
    ('family = "esp32"', 'family = "esp32"\nalso = ["rpi_pico"]', "[board] also", ["no pin named PWMA"]),
    ("[wiring]", '[report]\nviews = ["pool_lan"]\n\n[wiring]', "[report] views[0]", ["did you mean 'pool_lane'"]),
    (
        "start_pose = [1.0, 0.5, 0.0]",
        "start_pose = [1.0, 0.5, 0.0]\nobstacles = [[1.0, 0.5, 0.4, 0.4]]",
        "[plant] start_pose",
        ["inside an obstacle"],
    ),
    ("start_pose = [1.0, 0.5, 0.0]", "start_pose = [3.0, 0.5, 0.0]", "[plant] start_pose", ["outside"]),
    (
        "[wiring]",
        "[worlds.blocked]\nobstacles = [[1.0, 0.5, 0.4, 0.4]]\n\n[wiring]",
        "[worlds.blocked] start_pose",
        ["inside an obstacle"],
    ),
    (
        "[wiring]",
        '[worlds.moved]\n"imu.bus" = "i2c:16,17"\n\n[wiring]',
        "[worlds.moved] [[plant.parts]] #3 (imu) bus",
        ["PWMA"],
    ),
    ("[wiring]", POSE_LINE + "\n[wiring]", "[report.pose_line] probe", ["no pin is wired to 'probe:quantm'"]),
    ("[wiring]", '[[faults]]\nkind = "dropot"\n\n[wiring]', "[[faults]]", ["did you mean 'dropout'"]),
    ('source = "i2c0"\naddress = 0x29', 'source = "tof.rang"\naddress = 0x29', "[budgets.ranging] source", ["i2c0"]),
    ('entry = "main.py"', 'entry = "mian.py"', "[firmware] entry", ["did you mean 'main.py'"]),
    ('kind = "ssd1306"', 'kind = "neopixel"', "[[plant.parts]] #5 kind", ["ws2812_strip", "vl53l0x", "did you mean"]),
    ('kind = "ssd1306"', 'kind = "oled"', "[[plant.parts]] #5 kind", ["did you mean 'sh1106' or 'ssd1306'"]),
    ('body = "differential"', 'body = "diferential"', "[plant] body", ["did you mean 'differential'"]),
]


@pytest.mark.parametrize(("old", "new", "field", "says"), BAD_RIGS, ids=[f"{i}-{r[2]}" for i, r in enumerate(BAD_RIGS)])
def test_check_refuses_a_rig_that_cannot_mean_anything_naming_field_and_nearest(tmp_path, old, new, field, says):
    path = rig_with(tmp_path, old, new)
    with pytest.raises(ConfigError) as e:
        load_rig(path)
    message = str(e.value)
    assert message.startswith(f"{path}: {field}"), message
    for words in says:
        assert words in message, message


def test_a_wired_pin_past_the_familys_gpios_in_a_board_file_is_refused(tmp_path):
    path = rig_with(tmp_path, 'family = "esp32"', 'family = "esp32"\nfile = "board.py"')
    path.write_text(re.sub(r"\[board.pins\][^\[]*", "", path.read_text()))
    (path.parent / "board.py").write_text(
        "from micropython import const\nPWMA = const(99)\nAIN1 = 17\nAIN2 = 18\nPWMB = 4\nBIN1 = 23\nBIN2 = 19\n"
    )
    with pytest.raises(ConfigError, match=r"\[wiring\] PWMA: pin PWMA = 99: expected a GPIO from 0 to 48"):
        load_rig(path)


def test_an_unknown_part_kind_is_listed_whole_with_the_nearest(tmp_path):
    from sim_plant import catalogue

    path = rig_with(tmp_path, 'kind = "ssd1306"', 'kind = "neopixel"')
    result = subprocess.run([sys.executable, "-m", "host.cli", "check", str(path)], capture_output=True, text=True)
    assert result.returncode == 2
    for kind in catalogue.parts():
        assert kind in result.stderr, result.stderr
    assert "did you mean 'ws2812_strip'" in result.stderr


def test_the_rigs_of_the_repository_keep_the_rules():
    for path in [*REPO.glob("examples/*/rig.toml"), *REPO.glob("firmware/apps/*/rig*.toml")]:
        apps_of(path)  # (a rig file with several boards: each board's, docs/multi-board.md)


# -- nesting bombs ---------------------------------------------------------------------------


def test_a_nesting_bomb_is_named_with_its_line_and_column_by_every_reader(tmp_path):
    bomb = "[" * 100_000
    (tmp_path / "diagram.json").write_text(bomb)
    with pytest.raises(
        ConfigError,
        match=r"diagram.json: not JSON that can be read: nested deeper than 64 levels "
        r"at line 1, column 65",
    ):
        read_diagram(tmp_path / "diagram.json")
    (tmp_path / "s.test.yaml").write_text("name: x\nsteps:\n  - " + bomb)
    with pytest.raises(ScenarioError, match=r"nested deeper than 64 levels at line 3, column 69"):
        load_scenario(tmp_path / "s.test.yaml")
    (tmp_path / "b.test.yaml").write_text("steps:\n" + "- " * 100_000 + "x")
    with pytest.raises(ScenarioError, match="nested too deep"):
        load_scenario(tmp_path / "b.test.yaml")
    rig = rig_with(tmp_path, 'name = "oled_bot"', 'name = "oled_bot"\nbomb = ' + bomb)
    with pytest.raises(ConfigError, match=r"rig.toml: not valid TOML: nested deeper than 8 levels at line \d+, column"):
        load_rig(rig)
    with pytest.raises(ConfigError, match="trace.jsonl: not JSON that can be read: nested deeper"):
        loads_json("\n" + bomb, "trace.jsonl")


def test_too_deep_skips_brackets_in_strings_and_counts_lines():
    assert too_deep('{"a": ["[[[[[", {"b": "]]"}]}', limit=3) is None
    assert too_deep('{\n "a": [[[', limit=3) == "nested deeper than 3 levels at line 2, column 9"
    assert json.loads('{"x": [[1]]}') == loads_json(b'{"x": [[1]]}', "f")


def test_a_campaign_file_nested_past_reading_is_refused_by_name(tmp_path):
    from host.campaign import replay

    (tmp_path / "campaign.json").write_text("[" * 100_000)
    with pytest.raises(ConfigError, match="campaign.json: not JSON that can be read: nested deeper"):
        replay(tmp_path, "a/b/0")


# -- unknown pins ----------------------------------------------------------------------------


def test_a_wokwi_wire_to_a_pin_the_board_does_not_have_is_refused_with_its_pins(tmp_path):
    project = tmp_path / "p"
    shutil.copytree(REPO / "host" / "tests" / "wokwi_projects" / "devkit_v1_button", project)
    diagram = project / "diagram.json"
    diagram.write_text(diagram.read_text().replace('"esp:D2"', '"esp:99"'))
    with pytest.raises(
        ConfigError,
        match=r"connections\[4\]: esp:99: the ESP32 DevKit v1 has no pin '99' "
        r"\(its GPIOs: D0 to D39, TX0",
    ):
        read_diagram(diagram)
    diagram.write_text(diagram.read_text().replace('"esp:99"', '"esp:D40"'))
    with pytest.raises(ConfigError, match="has no pin 'D40'.*nearest: D4"):
        read_diagram(diagram)


@pytest.mark.parametrize(("pin", "refused"), [("ZZ", True), ("in", False), ("A", False), ("c", False), ("1.l", True)])
def test_a_scenario_pin_the_part_does_not_have_is_refused_with_its_pins(tmp_path, pin, refused):
    from host.rig import Recording, Rig, RigSpec
    from host.scenario.session import check_steps, prepare

    folder = tmp_path / "s"
    shutil.copytree(REPO / "host" / "tests" / "wokwi_scenarios" / "button_irq", folder)
    path = folder / "press.test.yaml"
    path.write_text(path.read_text().replace("pin: A", f"pin: {pin!r}", 1))
    scenario, app = prepare(path)
    rig = Rig(RigSpec(app), Recording())
    if refused:
        with pytest.raises(
            ScenarioError,
            match=rf"press.test.yaml:8: expect-pin: pin: part 'led1' has no pin "
            rf"'{re.escape(pin)}' \(its pins: in, A, C\)",
        ):
            check_steps(scenario, rig)
    else:
        check_steps(scenario, rig)


# -- escapes ---------------------------------------------------------------------------------

HOSTILE = "ready \x1b]0;owned\x07 \x1b]52;c;ZXZpbA==\x07 \x1b[2K\rlater\x9b\x00 tab\tkept"


def test_printable_escapes_every_control_a_terminal_acts_on_and_keeps_lines_and_tabs():
    shown = printable(HOSTILE + "\nnext")
    assert not re.search(r"[\x00-\x08\x0b-\x1f\x7f-\x9f]", shown)
    assert "\\x1b]0;owned\\x07" in shown and "\\x1b[2K\\rlater\\x9b\\x00" in shown
    assert "\tkept\nnext" in shown
    assert printable(b"\x1b[31m\xff") == "\\x1b[31m\ufffd"


ESCAPES_RIG = """name = "escapes"
[board]
family = "esp32"
[board.pins]
LED = 2
[plant]
body = "bench"
[[plant.parts]]
kind = "probe"
name = "led"
[wiring]
LED = "led.in"
"""


def escapes_app(tmp_path, main: str):
    (tmp_path / "main.py").write_text(main)
    (tmp_path / "rig.toml").write_text(ESCAPES_RIG)
    return load_rig(tmp_path / "rig.toml")


def test_firmware_escapes_are_escaped_in_an_expect_timeout_and_kept_raw_in_console_log(tmp_path, make_rig):
    main = f"import time\nprint({HOSTILE!r})\nwhile True:\n    time.sleep_ms(10)\n"
    rig = make_rig(escapes_app(tmp_path, main), artefacts=tmp_path / "out")
    with pytest.raises(ExpectTimeout) as e:
        rig.expect("never printed", timeout_s=0.2)
    message = str(e.value)
    assert "\x1b" not in message and "\r" not in message and "\x07" not in message
    assert "\\x1b]52;c;ZXZpbA==\\x07" in message
    assert "\x1b]52;c;ZXZpbA==\x07" in rig.console  # (what the firmware printed, for tests to read)
    rig.stop()
    assert "\x1b]52;c;ZXZpbA==\x07".encode() in (tmp_path / "out" / "console.log").read_bytes()


def test_a_firmware_exception_with_escapes_is_escaped_in_the_error(tmp_path, make_rig):
    main = 'print("\\x1b]0;title\\x07")\nraise ValueError("\\x1b[2J\\x1b]52;c;aGk=\\x07")\n'
    rig = make_rig(escapes_app(tmp_path, main))
    with pytest.raises(FirmwareError) as e:
        rig.run_for(0.2)
    assert "\x1b" not in str(e.value) and "\\x1b[2J\\x1b]52;c;aGk=\\x07" in str(e.value)
    assert "\x1b[2J" in e.value.traceback  # (the raw text stays on the error for a test to read)


def test_run_shows_the_console_with_escapes_escaped(capsys, tmp_path):
    cli._show_console(HOSTILE + "\n", tmp_path)
    out = capsys.readouterr().out
    assert "\x1b" not in out and "\r" not in out and "\\x1b]0;owned\\x07" in out


def test_a_trace_folder_or_campaign_nested_past_reading_is_refused_by_name_not_a_traceback(tmp_path):
    from host.artefacts.folder import load_trace
    from host.rig.loop import manifest
    from host.shrink.source import campaign_run

    bomb = "[" * 100_000
    (tmp_path / "header.json").write_text(bomb)
    with pytest.raises(ConfigError, match="header.json is not JSON"):
        load_trace(tmp_path)
    (tmp_path / "manifest.json").write_text(bomb)
    assert "not readable JSON" in manifest.read(tmp_path)["error"]
    (tmp_path / "campaign.json").write_text(bomb)
    with pytest.raises(ConfigError, match="campaign.json cannot be read \\(RecursionError"):
        campaign_run(tmp_path, "a/b/0")


def test_check_and_init_name_a_fifo_among_the_firmware_instead_of_waiting_on_it(tmp_path):
    import os

    shutil.copy(OLED_BOT / "main.py", tmp_path / "main.py")
    shutil.copy(OLED_BOT / "rig.toml", tmp_path / "rig.toml")
    os.mkfifo(tmp_path / "helper.py")
    run = [sys.executable, "-m", "host.cli"]
    checked = subprocess.run([*run, "check", str(tmp_path / "rig.toml")], capture_output=True, text=True, timeout=60)
    assert checked.returncode == 0, checked.stderr
    (line,) = [line for line in checked.stdout.splitlines() if "helper.py" in line]
    assert f"skipped {tmp_path / 'helper.py'}: " in line and "FIFO" in line and "not a file to read" in line, line
    (tmp_path / "rig.toml").unlink()
    started = subprocess.run([*run, "init", str(tmp_path)], capture_output=True, text=True, timeout=60)
    assert started.returncode == 0, started.stderr
    assert "helper.py: a FIFO" in started.stderr and (tmp_path / "rig.toml").is_file(), started.stderr


def test_what_diff_and_shrink_say_is_escaped(capsys, tmp_path, monkeypatch):
    body = "def command(args, say):\n    say('A: \\x1b]0;t\\x07 \\x1b[2K\\rB')\n    return 0\n"
    (tmp_path / "saying.py").write_text(body)
    monkeypatch.syspath_prepend(str(tmp_path))
    assert cli._say_command("saying", "command", None) == 0
    out = capsys.readouterr().out
    assert "\x1b" not in out and "\r" not in out and "\\x1b]0;t\\x07 \\x1b[2K\\rB" in out
