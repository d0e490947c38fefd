"""Wokwi projects (docs/wokwi.md): projects written here in Wokwi's format, on an ESP32
and on a Pico, run unchanged with every mapped part doing what Wokwi's would; the rig
file ``import-wokwi`` writes is the same rig; an unknown part or attribute is one line
naming it and the nearest we have; docs/wokwi.md's part table is the table's."""

import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from host.cli import main
from host.core.drivers import driver_folder
from host.core.errors import ConfigError
from host.rig.config.rigfile import load_rig
from host.rig.config.wokwi import docs
from host.rig.config.wokwi.project import import_wokwi, rig_from_project

PROJECTS = Path(__file__).parent / "wokwi_projects"
US_PER_CM = 58.31


def project(name: str, tmp_path: Path, oled: bool = True) -> Path:
    """A copy of a test project (its build/ stays in tmp), with the published SSD1306
    driver beside main.py as a Wokwi project has it."""
    folder = tmp_path / name
    shutil.copytree(PROJECTS / name, folder)
    if oled:
        shutil.copy(driver_folder("micropython-ssd1306") / "ssd1306.py", folder)
    return folder


def printed(console: str) -> dict:
    """The firmware's "key value..." lines: key -> the values (text), the last of each key."""
    found = {}
    for line in console.splitlines():
        key, *values = line.split()
        found[" ".join([key, *values[:-1]]) if key == "distance_cm" else key] = values[-1] if values else ""
    return found


def inner(rig):
    return getattr(rig.plant, "inner", rig.plant)


def test_an_esp32_project_runs_with_every_part(make_rig, tmp_path):
    rig = make_rig(str(project("esp32_parts", tmp_path)), plant_options={"btn1.presses": [[0.5, 0.6]]}, seed=1)
    rig.run_for(1.0)
    got, truth, plant = printed(rig.console), rig.plant.truth(), inner(rig)
    assert float(got["accel_z_g"]) == 1.0 and float(got["gyro_z_dps"]) == 10.0, "the IMU at rest, rotationZ 10"
    assert abs(float(got["distance_cm"]) - 123) < 0.5, "distance 123 cm"
    assert int(got["pot_u16"]) == round(512 / 1023 * 65535), "value 512 of 1023 on 3V3"
    assert abs(int(got["ldr_u16"]) - 65535 * 9.98 / (9.98 + 10)) < 20, "100 lux: 9.98 kOhm (Wokwi's table)"
    assert got["dark"] == "0" and got["switch"] == "1", "lit at 100 lux; the switch on the right, its 3V3 side"
    assert truth["led1_value"] == 1 and truth["led1_changes"] == 1, "the button's IRQ lit the LED once"
    assert abs(truth["servo1_angle_deg"] - 90) < 0.5, "1.5 ms at 50 Hz"
    assert truth["relay1_closed"] == 1 and truth["rgb1_rgb"] == 0x00FF00, "an NPN relay high; a common anode green"
    assert plant.output("ring1.led0") == 0xFF0000 and plant.output("ring1.led11") == 0x0000FF
    oled = next(p for p in plant.parts if getattr(p, "label", "") == "oled1")
    rows = oled.picture()
    assert sum(rows[: 128 * 8]) > 40 and sum(rows[128 * 8 :]) == 0, "Hello Wokwi in the first text row"
    assert rig.app.wiring["GPIO2"] == "probe:logic1_D0"


def test_a_pico_project_runs_with_every_part(make_rig, tmp_path):
    rig = make_rig(str(project("pico_parts", tmp_path)), plant_options={"btn1.presses": [[0.5, 0.6]]}, seed=1)
    rig.run_for(1.0)
    got, truth, plant = printed(rig.console), rig.plant.truth(), inner(rig)
    press = [line.split() for line in rig.console.splitlines() if line.startswith("press")]
    assert len(press) == 1, "one press to 3V3 seen by the rising-edge IRQ"
    assert float(got["accel_z_g"]) == 1.0 and int(got["who_am_i"]) == 0x68, "the MPU6050 at 0x69 (AD0 high)"
    assert abs(float(got["distance_cm 0"]) - 57) < 0.5 and abs(float(got["distance_cm 1"]) - 250) < 0.5
    assert int(got["pot_u16"]) == 65535 and int(got["slide_u16"]) == round(256 / 1023 * 65535)
    assert abs(int(got["ldr_u16"]) - 65535 * 250 / (250 + 10)) < 20, "1 lux: 250 kOhm (Wokwi's table)"
    assert got["dark"] == "1" and got["switch"] == "0", "dark at 1 lux; the switch on the left, its ground side"
    assert truth["led1_value"] == 16384, "a PWM LED: its duty"
    assert abs(truth["servo1_angle_deg"] - 45) < 0.5, "1 ms of a 500..2500 us servo"
    assert truth["relay1_closed"] == 1 and truth["rgb1_rgb"] == 0xFF00FF, "a PNP relay low; a common cathode magenta"
    assert plant.output("matrix1.led7") == 0x00FF00 and plant.output("px1.led0") == 0x0A141E
    assert sum(next(p for p in plant.parts if getattr(p, "label", "") == "oled1").picture()) > 30
    assert rig.app.wiring["GP17"] == "probe:logic1_D1" and rig.app.wiring["GP16"] == "led1.in", "D0 shares the LED's"


def test_a_devkit_v1_button_toggles_its_led_in_the_irq(make_rig):
    rig = make_rig(str(PROJECTS / "devkit_v1_button"), plant_options={"button.presses": [[0.25, 0.3], [0.7, 0.8]]})
    rig.run_for(1.0)
    lines = [line.split() for line in rig.console.splitlines() if line.startswith("toggled")]
    assert [int(v) for _, v, _ in lines] == [1, 0] and [int(ms) for *_, ms in lines] == [250, 700]
    assert rig.plant.truth()["blue_led_changes"] == 2 and rig.app.board.pins == {"D4": 4, "D2": 2}


def test_import_wokwi_writes_the_same_rig_and_keeps_an_existing_file(tmp_path):
    folder = project("pico_parts", tmp_path)
    made = rig_from_project(folder)
    path = import_wokwi(folder)
    text = path.read_text()
    assert "# wokwi-hc-sr04" in text and 'family = "rpi_pico"' in text
    loaded = load_rig(path)
    assert (loaded.wiring, loaded.board.pins, loaded.board.identity) == (
        made.wiring,
        made.board.pins,
        made.board.identity,
    )
    assert loaded.make_plant().describe() == made.make_plant().describe()
    with pytest.raises(ConfigError, match="exists: expected --force"):
        import_wokwi(folder)
    path.write_text("# mine\n")
    assert import_wokwi(folder, force=True).read_text() == text


def cli(*args, cwd=None) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "host.cli", *args], capture_output=True, text=True, cwd=cwd)


def broken(tmp_path: Path, change) -> Path:
    folder = project("devkit_v1_button", tmp_path, oled=False)
    diagram = json.loads((folder / "diagram.json").read_text())
    change(diagram)
    (folder / "diagram.json").write_text(json.dumps(diagram))
    return folder


@pytest.mark.parametrize(
    "change, message",
    [
        (
            lambda d: d["parts"].append({"type": "wokwi-ntc-temperature-sensor", "id": "ntc1", "attrs": {}}),
            r"parts\[3\] \('ntc1', wokwi-ntc-temperature-sensor\): not mapped \(no thermistor part\); nearest we ha",
        ),
        (
            lambda d: d["parts"][2].update(type="wokwi-ledd"),
            r"parts\[2\] \('blue_led', wokwi-ledd\): unknown part; nearest we have: 'wokwi-led'",
        ),
        (
            lambda d: d["parts"][1]["attrs"].update(colr="red"),
            r"parts\[1\] \('button', wokwi-pushbutton\): attrs.colr: unknown attribute; nearest: 'color'",
        ),
        (
            lambda d: d["parts"][0].update(type="wokwi-esp32-devkit-v2"),
            r"a board we do not run; nearest we have: 'wokwi-esp32-devkit-v1'",
        ),
        (
            lambda d: d["connections"].append(["button:2.r", "esp:3V3", "red", []]),
            r"button:2.l is wired to 3.3 and gnd: a short",
        ),
    ],
)
def test_an_unknown_part_or_attribute_is_one_line_and_exit_2(tmp_path, capsys, change, message):
    folder = broken(tmp_path, change)
    for command in (["run", str(folder), "--duration", "0.1"], ["import-wokwi", str(folder)], ["check", str(folder)]):
        assert main(command) == 2
        err = capsys.readouterr().err
        assert len(err.strip().splitlines()) == 1 and re.search(message, err), err
    assert not (folder / "rig.toml").exists()


def test_a_power_led_is_left_out_and_an_analyser_channel_shares_a_parts_pin(tmp_path):
    def extra(d):
        d["parts"] += [
            {"type": "wokwi-led", "id": "power", "attrs": {}},
            {"type": "wokwi-logic-analyzer", "id": "la", "attrs": {}},
        ]
        d["connections"] += [
            ["power:A", "esp:3V3", "", []],
            ["power:C", "esp:GND.1", "", []],
            ["la:D0", "esp:D2", "", []],
            ["la:D1", "esp:D5", "", []],
        ]

    app = rig_from_project(broken(tmp_path, extra))
    assert app.wiring == {"D4": "button.out", "D2": "blue_led.in", "D5": "probe:la_D1"}
    assert "power" not in app.make_plant().describe()


@pytest.mark.parametrize(
    "toml, message",
    [
        ('[wokwi]\nversion = 1\nfirmware = "micropython.bin"\n', None),
        ('[wokwi]\nversion = 1\nfirmwre = "micropython.bin"\n', r"\[wokwi\] firmwre: unknown key; nearest: 'firmware'"),
        ('[wokwi]\nversion = 1\n[[chip]]\nname = "x"\n', r"\[\[chip\]\]: custom chips are not run here"),
        ("[wokwi\n", r"wokwi.toml: not TOML"),
    ],
)
def test_wokwi_toml_changes_nothing_and_custom_chips_are_refused(tmp_path, toml, message):
    folder = project("devkit_v1_button", tmp_path, oled=False)
    (folder / "wokwi.toml").write_text(toml)
    if message is None:
        assert rig_from_project(folder).wiring == {"D4": "button.out", "D2": "blue_led.in"}
    else:
        with pytest.raises(ConfigError, match=message):
            rig_from_project(folder)


def test_an_attribute_out_of_its_bounds_names_its_unit(tmp_path):
    def far(d):
        d["parts"].append({"type": "wokwi-hc-sr04", "id": "s", "attrs": {"distance": "900"}})
        d["connections"] += [["s:TRIG", "esp:D5", "", []], ["s:ECHO", "esp:D18", "", []]]

    with pytest.raises(ConfigError, match=r"attrs.distance: expected a number of centimetres from 2 to 400, got '900'"):
        rig_from_project(broken(tmp_path, far))


def test_cli_import_then_check_and_run_take_the_rig_file(tmp_path, capsys):
    folder = project("devkit_v1_button", tmp_path, oled=False)
    assert main(["import-wokwi", str(folder)]) == 0 and (folder / "rig.toml").is_file()
    assert main(["import-wokwi", str(folder)]) == 2 and "--force" in capsys.readouterr().err
    assert main(["check", str(folder / "rig.toml")]) == 0
    assert "bench body with button button, probe blue_led" in capsys.readouterr().out
    run = cli("run", str(folder), "--duration", "0.5", "--no-plots", "--param", "button.presses=[[0.1, 0.2]]")
    assert run.returncode == 0 and "toggled 1 100" in run.stdout, run.stdout + run.stderr


def test_docs_wokwi_md_has_the_generated_part_table():
    text = docs.PAGE.read_text()
    assert docs.page_with_table(text) == text, "run: python -m host.rig.config.wokwi.docs"
    assert text.rstrip().endswith("## Scenarios") or "## Scenarios" in text
