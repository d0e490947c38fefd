"""The Pico-Go's 1.14" LCD (the ``st7789`` part on SPI1, hil_tests/firmware/picogo/rig.toml):
firmware in the style of Waveshare's demo (``ST7789.py``: a framebuf.RGB565 buffer sent in
one 64,800-byte ``spi.write``) and in the style of russhughes' ``st7789py`` (a rotation
table with its offsets, windows written in chunks, text blitted a glyph at a time) each
leave on the glass the picture they drew: colours at known places, the window, the
column and row offsets and the rotation honoured, and the trace folder has it as a PNG."""

import re
import shutil
from pathlib import Path

import pytest
from PIL import Image

from host.artefacts.pictures import scale_for

pytestmark = pytest.mark.hil
FIRMWARE = Path(__file__).parent / "firmware"


def run(make_rig, tmp_path, firmware: str):
    """The Pico-Go rig with ``firmware``'s files, run to its "done": (rig, the lcd chip, where)."""
    folder = tmp_path / firmware
    shutil.copytree(FIRMWARE / firmware, folder)
    shutil.copy(FIRMWARE / "picogo" / "rig.toml", folder / "rig.toml")
    out = tmp_path / "out"
    rig = make_rig(str(folder / "rig.toml"), allow_exit=True, artefacts=out, record=True)
    rig.expect("done")
    lcd = next(p for p in getattr(rig.plant, "inner", rig.plant).parts if getattr(p, "label", "") == "lcd")
    return rig, lcd, f"console:\n{rig.console}\nartefacts: {out}"


def pixel(picture: bytes, x: int, y: int, width: int = 240) -> int:
    """The glass's colour at (x, y), RGB565."""
    return picture[(y * width + x) * 2] << 8 | picture[(y * width + x) * 2 + 1]


def test_the_demos_framebuf_shown_in_one_write_lands_on_the_glass_byte_swapped_and_upright(make_rig, tmp_path):
    rig, lcd, where = run(make_rig, tmp_path, "picogo_lcd")
    picture = lcd.picture()
    truth = rig.truth()
    rig.stop()
    assert lcd.display_frames()[:2] == (240, 135), where
    assert truth["lcd_on"] == 1, f"expected the LCD awake, on and lit; truth {truth}; {where}"
    blue, orange = 0x00FF, 0xFF07  # (the demo's BLUE 0xFF00 and ORANGE 0x07FF as framebuf keeps them)
    for x, y, colour in ((0, 0, blue), (239, 134, blue), (144, 50, blue), (145, 49, blue), (210, 89, blue)):
        got = pixel(picture, x, y)
        assert got == colour, f"expected 0x{colour:04x} at ({x}, {y}), got 0x{got:04x}; {where}"
    for x, y in ((145, 50), (209, 50), (145, 89), (209, 89), (170, 70)):
        assert pixel(picture, x, y) == orange, f"the rectangle (145, 50, 65 x 40) at ({x}, {y}): {where}"
    for y, mask in re.findall(r"^text (\d+) ([0-9a-f]+)$", rig.console, re.M):
        drawn = int(mask, 16)
        shown = [pixel(picture, x, int(y)) == 0xFFFF for x in range(240)]
        assert shown == [bool(drawn >> (239 - x) & 1) for x in range(240)], f"the text's row {y}: {where}"
    spent_us = 64800 * 8 / 10e6 * 1e6
    us = int(re.search(r"^shown (\d+)$", rig.console, re.M).group(1))
    assert spent_us <= us < spent_us + 20_000, f"show() took {us} us, expected its 64,800 bytes at 10 MHz; {where}"
    png = Image.open(tmp_path / "out" / "lcd.png").convert("RGB")
    s = scale_for(240)
    assert png.size == (240 * s, 135 * s), where
    assert png.getpixel((0, 0)) == (0, 28, 255) and png.getpixel((170 * s, 70 * s)) == (255, 226, 57), where


def test_st7789py_style_windows_offsets_and_rotations_land_where_the_driver_drew_them(make_rig, tmp_path):
    rig, lcd, where = run(make_rig, tmp_path, "picogo_st7789py")
    picture = lcd.picture()
    frames = len(lcd.frames)
    rig.stop()
    assert "size 240 135" in rig.console, where
    red, green, blue, yellow, white = 0xF800, 0x07E0, 0x001F, 0xFFE0, 0xFFFF
    expected = {
        (0, 0): 0,
        (19, 30): 0,
        (20, 30): red,
        (69, 49): red,
        (70, 49): 0,
        (20, 50): 0,  # the filled rectangle
        (100, 40): green,
        (159, 40): green,
        (100, 69): green,
        (159, 69): green,
        (130, 40): green,  # its outline
        (101, 41): 0,
        (130, 55): 0,  # (inside the outline: still black)
        (200, 10): red,
        (201, 10): green,
        (200, 11): blue,
        (201, 11): white,
        (202, 10): 0,  # the blit, row by row
        (239, 134): white,  # the last pixel of the landscape glass
        (0, 134): 0x07FF,  # portrait's (0, 0): the glass's first row and column, bottom left as mounted
    }
    got = {xy: pixel(picture, *xy) for xy in expected}
    assert got == expected, f"expected {expected}, got {got}; {where}"
    h = [0x81, 0x81, 0x81, 0xFF, 0x81, 0x81, 0x81, 0x00]  # font8's "H" at (8, 100), "I" after it
    i = [0x3C, 0x18, 0x18, 0x18, 0x18, 0x18, 0x3C, 0x00]
    for row in range(8):
        drawn = [yellow if (h[row] << 8 | i[row]) >> (15 - x) & 1 else blue for x in range(16)]
        shown = [pixel(picture, 8 + x, 100 + row) for x in range(16)]
        assert shown == drawn, f"the text's row {row}: expected {drawn}, got {shown}; {where}"
    gif = Image.open(tmp_path / "out" / "lcd.gif")
    assert gif.n_frames == frames >= 6, f"a picture for each drawing that changed the glass: {frames}; {where}"
    s = scale_for(240)
    assert Image.open(tmp_path / "out" / "lcd.png").convert("RGB").getpixel((20 * s, 30 * s)) == (255, 0, 0), where
