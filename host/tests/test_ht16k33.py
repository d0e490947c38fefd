"""The ht16k33 part (docs/parts.md) on the Keyestudio Beetlebot's rig (ESP32), driven as
the published HT16K33 matrix drivers drive it (a command a transfer; a frame as the RAM
pointer 0 and 16 bytes, a row's byte and a zero byte each): the matrix shows each icon,
upright, at the instant it was written, the RAM reads back from the pointer, and the trace
folder has the picture."""

import pytest
from PIL import Image

from host.artefacts.pictures import SCALE
from host.kits import kit

FIRMWARE = """
import time
from machine import I2C, Pin

i2c = I2C(scl=Pin(22), sda=Pin(21))
ADDRESS = 0x70

def command(byte):
    i2c.writeto(ADDRESS, bytes([byte]))

def draw(icon):
    frame = bytearray(17)
    for i in range(8):
        frame[i * 2 + 1] = icon[i]
    i2c.writeto(ADDRESS, bytes(frame))

print('found', i2c.scan())
command(0x21)  # the oscillator on
command(0x81)  # the display on, no blink
command(0xE0 | 5)
draw(b"\\x18\\x18\\x18\\x18\\x18\\x00\\x00\\x18")
time.sleep_ms(100)
draw(b"\\x48\\x24\\x12\\x09\\x09\\x12\\x24\\x48")
i2c.writeto(ADDRESS, b"\\x02")
print('ram', list(i2c.readfrom(ADDRESS, 4)))
time.sleep_ms(100)
command(0x80)  # the display off
print('done')
"""


@pytest.mark.hil
def test_an_ht16k33_matrix_shows_each_icon_upright_and_its_ram_reads_back(make_rig, tmp_path):
    (tmp_path / "rig.toml").write_text((kit("keyestudio_beetlebot").folder / "rig.toml").read_text())
    (tmp_path / "main.py").write_text(FIRMWARE)
    rig = make_rig(str(tmp_path / "rig.toml"), allow_exit=True, artefacts=tmp_path / "out", record=True)
    assert rig.expect(r"found (.*)\n").group(1) == "[112]", rig.console
    ram = rig.expect(r"ram (.*)\n").group(1)
    rig.expect("done\n")
    matrix = next(p for p in getattr(rig.plant, "inner", rig.plant).parts if getattr(p, "label", "") == "matrix")
    truth = rig.truth()
    rig.stop()
    assert ram == "[36, 0, 18, 0]", f"RAM 2..5 (rows 1 and 2 of the left arrow and their zero bytes): {ram}"
    shown = [(t, ["".join(".#"[v] for v in pic[y * 8 : y * 8 + 8]) for y in range(8)]) for t, pic in matrix.frames]
    stop = ["...##..."] * 5 + ["........"] * 2 + ["...##..."]
    left = ["...#..#.", "..#..#..", ".#..#...", "#..#....", "#..#....", ".#..#...", "..#..#..", "...#..#."]
    dark = ["........"] * 8  # (at power-on, the first transfer: the scan)
    assert [rows for _t, rows in shown] == [dark, stop, left, dark], shown
    t_stop, t_left, t_off = (t for t, _rows in shown[1:])
    assert 90_000 <= t_left - t_stop <= 110_000 and 90_000 <= t_off - t_left <= 110_000, [t for t, _ in shown]
    assert (truth["matrix_on"], truth["matrix_dimming"], truth["matrix_lit_px"]) == (0, 5, 0), truth
    png = Image.open(tmp_path / "out" / "matrix.png").convert("L")
    assert not any(png.getpixel((x * SCALE, y * SCALE)) for y in range(8) for x in range(8)), "the last: dark"
