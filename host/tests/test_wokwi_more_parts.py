"""The Wokwi parts a survey of public MicroPython projects finds common beside the first
ones (docs/wokwi.md): an I2C LCD1602 / LCD2004 driven by an lcd_api.py / i2c_lcd.py pair,
a buzzer's tones, a KY-040 knob's turns and presses; on an ESP32 and on a Pico."""

import shutil
from pathlib import Path

import pytest

from host.core.errors import ConfigError
from host.wokwi.project import rig_from_project

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
