"""The st7789 part (sim_plant/catalogue/st7789.py) played as the shim's BUS frames play it:
commands and parameters by D/C, the window and the write's counters, where MADCTL puts a
pixel (so the drivers' offsets land on the glass), inversion, colour order, sleep, the
backlight, reset, the glass turned as mounted, and the refusals."""

import pytest

from sim_plant import buses as B
from sim_plant.catalogue.assembly import assemble
from sim_plant.catalogue.base import PartsError

RED, GREEN, BLUE, WHITE = 0xF800, 0x07E0, 0x001F, 0xFFFF


def tft(**options):
    p = assemble({"body": "bench", "parts": [{"kind": "st7789", "name": "tft", "bus": "spi1", **options}]})
    p.set_input("tft.cs", 0)
    return p, next(d for d in p.bus_set.devices if d.label == "tft")


def send(p, command, *params):
    p.set_input("tft.dc", 0)
    p.bus_transfer("spi1", B.SPI_XFER, 0, 0, bytes((command,)))
    if params:
        p.set_input("tft.dc", 1)
        p.bus_transfer("spi1", B.SPI_XFER, 0, 0, bytes(params))


def awake(p, madctl=0x00):
    for c in (0x01, 0x11, 0x13, 0x21, 0x29):
        send(p, c)
    send(p, 0x3A, 0x55)
    send(p, 0x36, madctl)


def window(p, x0, y0, x1, y1, *colours):
    send(p, 0x2A, x0 >> 8, x0 & 0xFF, x1 >> 8, x1 & 0xFF)
    send(p, 0x2B, y0 >> 8, y0 & 0xFF, y1 >> 8, y1 & 0xFF)
    send(p, 0x2C, *b"".join(c.to_bytes(2, "big") for c in colours))


def at(chip, x, y) -> int:
    w, _h = chip.size()
    picture = chip.picture()
    return picture[(y * w + x) * 2] << 8 | picture[(y * w + x) * 2 + 1]


def test_a_window_is_filled_row_by_row_from_its_start_and_the_135x240_glass_starts_at_52_40():
    p, chip = tft()
    awake(p)
    window(p, 52, 40, 53, 41, RED, GREEN, BLUE, WHITE, RED)  # (the fifth: back to the start)
    assert chip.size() == (135, 240)
    assert [at(chip, 0, 0), at(chip, 1, 0), at(chip, 0, 1), at(chip, 1, 1)] == [RED, GREEN, BLUE, WHITE]
    window(p, 51, 39, 51, 39, RED)  # (off the glass: in memory, not shown)
    assert p.truth()["tft_lit_px"] == 4


@pytest.mark.parametrize(
    "madctl, xstart, ystart, width, height",
    [(0x00, 52, 40, 135, 240), (0x60, 40, 53, 240, 135), (0xC0, 53, 40, 135, 240), (0xA0, 40, 52, 240, 135)],
)
def test_each_rotation_of_st7789py_with_its_offsets_covers_the_135x240_glass_exactly(
    madctl, xstart, ystart, width, height
):
    p, chip = tft()
    awake(p, madctl)
    window(p, xstart, ystart, xstart + width - 1, ystart + height - 1, *[WHITE] * (width * height))
    assert p.truth()["tft_lit_px"] == 135 * 240, "every pixel of the glass written, none past it"


def test_the_picogo_demos_window_with_madctl_0x70_is_the_glass_turned_and_its_text_upright():
    p, chip = tft(turn_deg=270)
    awake(p, 0x70)
    assert chip.size() == (240, 135)
    window(p, 40, 53, 279, 187, *[BLUE] * (240 * 135))
    window(p, 40 + 10, 53 + 5, 40 + 12, 53 + 5, RED, GREEN, WHITE)  # a row of three at (10, 5)
    assert [at(chip, x, 5) for x in (9, 10, 11, 12, 13)] == [BLUE, RED, GREEN, WHITE, BLUE]
    assert at(chip, 10, 6) == BLUE and at(chip, 239, 134) == BLUE


def test_the_240x240_glass_upside_down_needs_st7789py_s_row_offset_of_80():
    p, chip = tft(panel="240x240")
    awake(p, 0xC0)
    window(p, 0, 80, 0, 80, RED)  # its (0, 0) upside down: the glass's bottom right
    assert at(chip, 239, 239) == RED


def test_inversion_colour_order_sleep_the_backlight_and_reset():
    p, chip = tft()
    awake(p)
    window(p, 52, 40, 52, 40, RED)
    assert at(chip, 0, 0) == RED, "an IPS glass shows true colours with INVON"
    send(p, 0x20)
    assert at(chip, 0, 0) == RED ^ 0xFFFF
    send(p, 0x21)
    send(p, 0x36, 0x08)
    assert at(chip, 0, 0) == BLUE, "BGR set on an RGB glass: red and blue exchanged"
    send(p, 0x36, 0x00)
    p.set_input("tft.bl", 0)
    assert sum(chip.picture()) == 0 and p.truth()["tft_on"] == 0
    p.set_input("tft.bl", 1)
    send(p, 0x10)
    assert sum(chip.picture()) == 0, "asleep: dark"
    send(p, 0x11)
    assert at(chip, 0, 0) == RED
    p.set_input("tft.res", 0)
    assert sum(chip.picture()) == 0 and not chip.awake and not chip.on
    assert chip.display_frames()[2][-1][1] == chip.picture()


def test_extra_data_after_a_command_is_ignored_and_a_write_continues_with_ramwrc():
    p, chip = tft()
    for c in (0x11, 0x13, 0x21, 0x29):
        send(p, c, 0x00)  # (st7789py's init: a zero byte after each)
    window(p, 52, 40, 54, 40, RED)
    send(p, 0x3C, *GREEN.to_bytes(2, "big"))
    assert [at(chip, x, 0) for x in range(4)] == [RED, GREEN, 0, 0]


@pytest.mark.parametrize(
    "options, message",
    [({"bus": "i2c0"}, "bus: expected an SPI bus"), ({"panel": "128x64"}, "panel"), ({"turn_deg": 45}, "turn_deg")],
)
def test_refusals(options, message):
    with pytest.raises(PartsError, match=message):
        assemble({"body": "bench", "parts": [{"kind": "st7789", "name": "tft", **options}]})


def test_a_snapshot_of_the_plant_keeps_the_frame_memory_and_restore_puts_it_back():
    p, chip = tft()
    awake(p)
    window(p, 52, 40, 52, 40, RED)
    snap = p.snapshot()
    window(p, 52, 40, 52, 40, GREEN)
    assert at(chip, 0, 0) == GREEN
    p.restore(snap)
    chip = next(d for d in p.bus_set.devices if d.label == "tft")
    assert at(chip, 0, 0) == RED, "a rewind puts the pixels back"
