"""The Wokwi parts a survey of public MicroPython projects finds common beside the first
ones (docs/wokwi.md): an I2C LCD1602 / LCD2004 driven by an lcd_api.py / i2c_lcd.py pair,
a buzzer's tones, a KY-040 knob's turns and presses, a DHT11 read by the dht module (the
DHT22 and set-control: host/tests/wokwi_scenarios/dht_knob); on an ESP32 and on a Pico."""

import json
import shutil
from pathlib import Path

import pytest

from host.cli import main
from host.core.errors import ConfigError
from host.rig.config.wokwi.project import rig_from_project

PROJECTS = Path(__file__).parent / "wokwi_projects"


def printed(console: str) -> dict:
    return {line.split(" ", 1)[0]: line.split(" ", 1)[1] for line in console.splitlines() if " " in line}


def part(rig, label: str):
    plant = getattr(rig.plant, "inner", rig.plant)
    return next(p for p in plant.parts if getattr(p, "label", "") == label)


def test_an_esp32_lcd1602_buzzer_and_ky040(make_rig):
    rig = make_rig(
        str(PROJECTS / "esp32_lcd_knob"),
        plant_options={"knob1.turns": [[0.4, 3], [0.5, -1]], "knob1.presses": [[0.55, 0.6]]},
    )
    rig.run_for(1.2)
    got = printed(rig.console)
    assert got["found"] == "['0x27']" and got["position"] == "2" and got["pressed"] == "[2]"
    lcd = part(rig, "lcd1")
    assert lcd.lines() == ["Hello Wokwi     ", "pos 2           "]
    assert "Hello Wokwi     \nLCD 1602        " in [text for _, text in lcd.screens], "before the knob's line"
    truth = rig.plant.truth()
    assert truth["lcd1_backlight"] == 1 and truth["knob1_position"] == 2
    bz = part(rig, "bz1")
    assert [freq for _, _, freq in bz.tones] == [440, 880] and truth["bz1_freq_hz"] == 0
    (t0, t1, _), (t2, t3, _) = bz.tones
    assert t1 == t2 and t1 - t0 == pytest.approx(100_000, abs=2_000) and t3 - t2 == pytest.approx(100_000, abs=2_000)


def test_a_pico_lcd2004_at_0x3f_its_four_rows_beeps_and_a_polled_knob(make_rig):
    rig = make_rig(
        str(PROJECTS / "pico_lcd2004"),
        plant_options={"knob1.turns": [[0.5, -2], [0.6, 5]], "knob1.presses": [[0.7, 0.75], [0.8, 0.85]]},
    )
    rig.run_for(1.2)
    got = printed(rig.console)
    assert got["position"] == "3" and got["presses"] == "2" and "done" in rig.console
    lcd = part(rig, "lcd1")
    rows = next(text for _, text in lcd.screens if "row three" in text).split("\n")
    assert [r.rstrip() for r in rows] == ["row zero", " row one", "  row two", "   row three"]
    assert [len(r) for r in rows] == [20] * 4 and lcd.lines()[0].rstrip() == "knob 3"
    bz = part(rig, "bz1")
    assert [freq for _, _, freq in bz.tones] == [1000, 1500, 2000] and rig.plant.truth()["bz1_tones"] == 3
    assert all(t1 - t0 == pytest.approx(50_000, abs=2_000) for t0, t1, _ in bz.tones)


@pytest.mark.parametrize(
    "attrs, message",
    [
        ({"pins": "full"}, r'attrs.pins: only "i2c"'),
        ({"pins": "i2c", "i2cAddress": "0x99"}, r"attrs.i2cAddress: expected a number from 8 to 119"),
    ],
)
def test_an_lcd_on_its_parallel_pins_or_a_bad_address_is_refused(tmp_path, attrs, message):
    folder = tmp_path / "p"
    shutil.copytree(PROJECTS / "esp32_lcd_knob", folder)
    text = (folder / "diagram.json").read_text()
    (folder / "diagram.json").write_text(
        text.replace('{ "pins": "i2c", "background": "blue", "color": "white" }', str(attrs).replace("'", '"'))
    )
    with pytest.raises(ConfigError, match=message):
        rig_from_project(folder)


def dht11_reply_us(data: bytes) -> int:
    """The read's length after the start (10 us, the sensor's 30 us wake, its 160 us preamble,
    40 bits of 50 us low and 26 or 70 us high, its last 50 us low), as _hildht.py times it."""
    ones = sum(bin(b).count("1") for b in data)
    return 10 + 30 + 160 + 40 * 50 + ones * 70 + (40 - ones) * 26 + 50


def test_a_pico_dht11_read_by_the_dht_module_takes_the_protocols_time(make_rig):
    rig = make_rig(str(PROJECTS / "pico_dht11"))
    rig.run_for(3.5)
    reads = [line.split() for line in rig.console.splitlines() if line.startswith("dht")]
    assert [r[1:3] for r in reads] == [["31", "62"]] * 3
    length_us = 250_000 + 18_000 + dht11_reply_us(bytes((62, 0, 31, 0, 93)))
    assert all(abs(int(r[3]) - length_us) < 300 for r in reads), (reads, length_us)
    assert rig.plant.truth()["dht1_reads"] == 3


def test_a_dht_read_with_no_sensor_on_its_pin_times_out(make_rig, tmp_path):
    folder = tmp_path / "no_dht"
    shutil.copytree(PROJECTS / "pico_dht11", folder)
    diagram = json.loads((folder / "diagram.json").read_text())
    diagram["parts"] = [p for p in diagram["parts"] if p["id"] != "dht1"]
    diagram["connections"] = [c for c in diagram["connections"] if not c[0].startswith("dht1:")]
    (folder / "diagram.json").write_text(json.dumps(diagram))
    rig = make_rig(str(folder))
    rig.run_for(1.5)
    errors = [line.split() for line in rig.console.splitlines() if line.startswith("dht error")]
    assert errors and errors[0][2] == "110" and abs(int(errors[0][3]) - 268_110) < 300, rig.console


def test_check_reads_a_dht_sensors_pin_as_its_line(capsys):
    assert main(["check", str(PROJECTS / "pico_dht11")]) == 0
    said = "".join(capsys.readouterr())
    assert "plant: bench body with dht dht1" in said
    first, *rest = said.splitlines()
    assert first.endswith("ok (0 pins wired; its parts are on dht:28)"), said
    rest = "\n".join(rest)
    assert "dht:28" not in rest and "Pin(28)" not in rest, "the code's DHT22(Pin(28)) is the line dht:28"
