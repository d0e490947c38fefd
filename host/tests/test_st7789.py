"""The st7789 part (docs/parts.md) with a 240 x 240 panel, driven the way russhughes'
st7789py drives Waveshare's Pico-LCD-1.3 (written here, not copied): upside down its
rotation table adds 80 to the row (MADCTL 0xC0) or to the column (0xA0), the memory's 320
rows mirrored onto the glass's 240, and what it drew lands there. Its bus readings are
compared with and without the bus images (host/tests/test_bus_image.py)."""

import pytest

from host.tests.conftest import FIRMWARE, bench_app

pytestmark = pytest.mark.hil

PLANT = {"body": "bench", "parts": [{"kind": "st7789", "name": "tft", "bus": "spi1", "panel": "240x240"}]}
WIRING = {"TFT_DC": "tft.dc", "TFT_CS": "tft.cs", "TFT_RST": "tft.res", "TFT_BL": "tft.bl"}
PINS = {"TFT_DC": 8, "TFT_CS": 9, "TFT_RST": 12, "TFT_BL": 13}


def test_a_square_panel_upside_down_shows_what_st7789py_s_offsets_of_80_draw(make_rig, tmp_path):
    app = bench_app("st7789_square", PLANT, board="rpi_pico_bench", wiring=WIRING, pins=PINS)
    rig = make_rig(app, main_dir=FIRMWARE / "st7789_square", allow_exit=True, artefacts=tmp_path / "out")
    rig.expect("done")
    tft = next(p for p in getattr(rig.plant, "inner", rig.plant).parts if getattr(p, "label", "") == "tft")
    picture, truth = tft.picture(), rig.plant.truth()
    rig.stop()

    def at(x, y):
        return picture[(y * 240 + x) * 2] << 8 | picture[(y * 240 + x) * 2 + 1]

    where = f"console:\n{rig.console}\nartefacts: {tmp_path / 'out'}"
    expected = {
        (239, 239): 0xF800,  # rotation 2's (0, 0): the glass's last pixel
        (229, 219): 0x07E0, (200, 180): 0x07E0, (230, 219): 0, (229, 220): 0, (199, 180): 0,  # its 30 x 40 at (10, 20)
        (0, 239): 0x001F,  # rotation 3's (0, 0): bottom left
        (0, 0): 0, (120, 120): 0,
    }  # fmt: skip
    got = {xy: at(*xy) for xy in expected}
    assert got == expected, f"expected {expected}, got {got}; {where}"
    assert truth["tft_lit_px"] == 2 + 30 * 40 and truth["tft_on"] == 1, f"truth {truth}; {where}"
