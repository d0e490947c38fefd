"""The sh1106 part (docs/parts.md) under a driver written as the public MicroPython SH1106
drivers are (no published one on the package index: host/tests/firmware/oled_sh1106), on
I2C and on SPI with D/C and CS: the 128-pixel glass shows RAM columns 2 to 129 (the
drivers' column offset), pixel for pixel what MicroPython's framebuf draws, and the trace
folder and report have its picture."""

import json

import pytest
from PIL import Image

from host.artefacts.pictures import SCALE
from host.report.html import RigResult, _displays
from host.tests.conftest import FIRMWARE, bench_app, results
from host.tests.test_oled import vlsb_rows
from sim_plant import buses as B
from sim_plant.catalogue.assembly import assemble

PLANT = {
    "body": "bench",
    "parts": [
        {"kind": "sh1106", "name": "oled", "bus": "i2c0"},
        {"kind": "sh1106", "name": "other", "bus": "spi1", "spi": True},
    ],
}


@pytest.mark.hil
def test_an_sh1106_driver_at_column_offset_two_shows_what_framebuf_draws_on_i2c_and_spi(make_rig, tmp_path):
    app = bench_app(
        "oled_sh1106",
        PLANT,
        wiring={"OLED_DC": "other.dc", "OLED_RES": "other.res", "OLED_CS": "other.cs"},
        pins={"OLED_DC": 4, "OLED_RES": 5, "OLED_CS": 15},
    )
    rig = make_rig(app, main_dir=FIRMWARE / "oled_sh1106", allow_exit=True, artefacts=tmp_path, record=True)
    rig.run_for(0.5)
    parts = {getattr(p, "label", ""): p for p in getattr(rig.plant, "inner", rig.plant).parts}
    rig.stop()
    r = results(rig.console)
    assert r["same"] == 1, rig.console
    expected = vlsb_rows(r["ref"], 128, 64)
    assert sum(expected) == r["lit"] > 300
    assert parts["oled"].picture() == expected, "the glass shows what framebuf drew"
    other = parts["other"].picture()
    assert other == vlsb_rows(r["other"], 128, 64)
    assert all(other[y * 128 + 127] for y in range(64)), "the last column lit: RAM column 129"
    assert parts["oled"].ram[0] == parts["oled"].ram[1] == 0, "columns 0 and 1 are off the glass"
    assert rig.plant.truth()["oled_lit_px"] == r["lit"] and rig.plant.truth()["oled_on"] == 1
    png = Image.open(tmp_path / "oled.png").convert("L")
    lit = [png.getpixel((x * SCALE, y * SCALE)) > 0 for y in range(64) for x in range(128)]
    assert bytes(lit) == expected, "the PNG is the picture"
    html = "".join(
        _displays(RigResult("rig0", tmp_path, header=json.loads((tmp_path / "header.json").read_text())), tmp_path)
    )
    assert 'src="oled.png"' in html and 'href="oled.gif"' in html and 'src="other.png"' in html


def i2c(p, *bytes_):
    assert p.bus_transfer("i2c0", B.XFER, 0x3C, 0, bytes(bytes_))[0] == B.OK


def test_the_sh1106_has_only_page_addressing_its_column_stops_at_131_and_the_glass_starts_at_segment_2():
    p = assemble({"body": "bench", "parts": [{"kind": "sh1106", "name": "oled", "bus": "i2c0"}]})
    chip = p.bus_device("i2c0", 0x3C)
    i2c(p, 0x00, 0x20, 0x00, 0xA1, 0xC8, 0xAF)  # (0x20 0x00: the SSD1306's horizontal mode; no command here)
    i2c(p, 0x00, 0xB3, 0x00, 0x18)  # page 3, column 0x80
    i2c(p, 0x40, *[0xFF] * 6)  # columns 128 to 131, then 131 again
    assert chip.ram[3 * 132 + 128 : 3 * 132 + 132] == [0xFF] * 4 and chip.page == 3 and chip.col == 131
    assert chip.ram[4 * 132] == 0, "no wrap onto the next page"
    i2c(p, 0x00, 0xB0, 0x02, 0x10)  # page 0, column 2: the glass's first
    i2c(p, 0x40, 0x01)
    assert chip.picture()[:128] == b"\x01" + bytes(127), "row 0: x 0 only"
    assert chip.picture()[24 * 128 : 25 * 128] == bytes(126) + b"\x01\x01", "RAM 128-129 at 126-127"
    i2c(p, 0x00, 0xA0)  # no remap: mirrored, glass x from RAM column 129 - x
    assert chip.picture()[:128] == bytes(127) + b"\x01"
