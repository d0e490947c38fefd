"""The ssd1306 part (docs/parts.md) under the published micropython-ssd1306 driver,
unchanged (host/core/drivers.txt), on I2C (128x64) and SPI (128x32): the picture on the
glass is the text the firmware drew, pixel for pixel what MicroPython's framebuf draws
for that text, and the trace folder has it as a PNG and a GIF."""

import json

import pytest
from PIL import Image

from host.artefacts.pictures import SCALE
from host.core.drivers import driver_folder
from host.report.html import RigResult, _displays
from host.tests.conftest import FIRMWARE, bench_app, results

pytestmark = pytest.mark.hil

PLANT = {
    "body": "bench",
    "parts": [
        {"kind": "ssd1306", "name": "oled", "bus": "i2c0"},
        {"kind": "ssd1306", "name": "small", "bus": "spi1", "spi": True, "height": 32},
    ],
}


def vlsb_rows(buffer: list, width: int, height: int) -> bytes:
    """A MONO_VLSB frame buffer as rows of pixels (a byte each: 0 or 1)."""
    return bytes(buffer[(y >> 3) * width + x] >> (y & 7) & 1 for y in range(height) for x in range(width))


def test_published_ssd1306_driver_shows_the_text_framebuf_draws_on_i2c_and_spi(make_rig, tmp_path):
    app = bench_app(
        "oled_text",
        PLANT,
        lib_dirs=(driver_folder("micropython-ssd1306"),),
        wiring={"OLED_DC": "small.dc", "OLED_RES": "small.res", "OLED_CS": "small.cs"},
        pins={"OLED_DC": 4, "OLED_RES": 5, "OLED_CS": 15},
    )
    rig = make_rig(app, main_dir=FIRMWARE / "oled_text", allow_exit=True, artefacts=tmp_path, record=True)
    rig.run_for(0.5)
    oled = next(p for p in getattr(rig.plant, "inner", rig.plant).parts if getattr(p, "label", "") == "oled")
    small = next(p for p in getattr(rig.plant, "inner", rig.plant).parts if getattr(p, "label", "") == "small")
    rig.stop()
    r = results(rig.console)
    assert r["same"] == 1, rig.console
    expected = vlsb_rows(r["ref"], 128, 64)
    assert sum(expected) == r["lit"] > 100
    assert oled.picture() == expected, "the glass shows what framebuf drew"
    assert small.picture() == vlsb_rows(r["small"], 128, 32)
    assert sum(small.picture()[: 128 * 8]) == 0 and sum(small.picture()[128 * 8 : 128 * 16]) > 30, "row 8 to 15"
    assert rig.plant.truth()["oled_lit_px"] == r["lit"] and rig.plant.truth()["oled_on"] == 1
    png = Image.open(tmp_path / "oled.png").convert("L")
    assert png.size == (128 * SCALE, 64 * SCALE)
    lit = [png.getpixel((x * SCALE, y * SCALE)) > 0 for y in range(64) for x in range(128)]
    assert bytes(lit) == expected, "the PNG is the picture"
    gif = Image.open(tmp_path / "oled.gif")
    assert gif.n_frames == oled.display_frames()[2].__len__() >= 2  # (the cleared screen, then the text)
    html = "".join(
        _displays(RigResult("rig0", tmp_path, header=json.loads((tmp_path / "header.json").read_text())), tmp_path)
    )
    assert 'src="oled.png"' in html and 'href="oled.gif"' in html and 'src="small.png"' in html
