"""The ssd1306 part (sim_plant/catalogue/ssd1306.py) played as the shim's BUS frames play
it: the I2C control bytes, the three addressing modes, the status byte, what the glass
shows (remaps, inverse, entire on, off), the SPI D/C and reset pins, and the refusals."""

import pytest

from sim_plant import buses as B
from sim_plant.catalogue.assembly import assemble
from sim_plant.catalogue.base import PartsError


def oled(**options):
    p = assemble({"body": "bench", "parts": [{"kind": "ssd1306", "name": "oled", **options}]})
    return p, next(d for d in p.bus_set.devices if d.label == "oled")


def cmds(p, *commands):
    assert p.bus_transfer("i2c0", B.XFER, 0x3C, 0, bytes((0x00, *commands)))[0] == B.OK


def data(p, *values):
    assert p.bus_transfer("i2c0", B.XFER, 0x3C, 0, bytes((0x40, *values)))[0] == B.OK


def lit(chip) -> set:
    picture = chip.picture()
    return {(i % 128, i // 128) for i, v in enumerate(picture) if v}


def test_the_status_byte_says_whether_the_display_is_on():
    p, chip = oled()
    assert p.bus_transfer("i2c0", B.XFER, 0x3C, 1, b"")[2] == bytes((0x46,))
    cmds(p, 0xAF)
    assert p.bus_transfer("i2c0", B.XFER, 0x3C, 1, b"")[2] == bytes((0x06,))
    assert p.bus_transfer("i2c0", B.XFER, 0x3D, 1, b"")[0] == B.NACK_ADDRESS


def test_horizontal_addressing_wraps_within_the_column_and_page_ranges_and_the_glass_shows_it_upright():
    p, chip = oled()
    cmds(p, 0xA1, 0xC8, 0x20, 0x00, 0x21, 10, 11, 0x22, 2, 3, 0xAF)
    data(p, 0x01, 0x80, 0x01, 0x80)
    assert lit(chip) == {(10, 16), (11, 23), (10, 24), (11, 31)}
    cmds(p, 0xA0)  # segments not remapped: mirrored
    assert lit(chip) == {(117, 16), (116, 23), (117, 24), (116, 31)}
    cmds(p, 0xA1, 0xC0)  # COM scan not remapped: upside down
    assert lit(chip) == {(10, 47), (11, 40), (10, 39), (11, 32)}


def test_vertical_and_page_addressing_and_the_control_byte_with_co_set():
    p, chip = oled()
    cmds(p, 0xA1, 0xC8, 0xAF, 0x20, 0x01, 0x21, 0, 1, 0x22, 0, 1)
    data(p, 0x01, 0x01, 0x01)  # (0,0), (0,8), then the next column: (1,0)
    assert lit(chip) == {(0, 0), (0, 8), (1, 0)}
    # page mode (0x02) by single commands (Co = 1: a control byte before each byte)
    assert p.bus_transfer("i2c0", B.XFER, 0x3C, 0, bytes((0x80, 0x20, 0x80, 0x02, 0x80, 0xB7, 0x80, 0x05, 0x80, 0x12)))
    data(p, 0x80, 0x80)
    assert {(37, 63), (38, 63)} <= lit(chip)


def test_inverse_entire_on_and_off():
    p, chip = oled(height=32)
    cmds(p, 0xA1, 0xC8, 0xA8, 31)
    assert sum(chip.picture()) == 0, "off: dark"
    cmds(p, 0xAF, 0xA7)
    assert sum(chip.picture()) == 128 * 32
    cmds(p, 0xA6, 0xA5)
    assert sum(chip.picture()) == 128 * 32
    cmds(p, 0xA4)
    assert sum(chip.picture()) == 0
    assert p.truth()["oled_on"] == 1


def test_spi_bytes_are_commands_or_data_by_dc_and_reset_turns_it_off():
    p, chip = oled(bus="spi1", spi=True)
    assert set(p.inputs) >= {"oled.cs", "oled.dc", "oled.res"}
    p.set_input("oled.cs", 0)
    p.set_input("oled.dc", 0)
    p.bus_transfer("spi1", B.SPI_XFER, 0, 0, bytes((0xA1, 0xC8, 0xAF, 0x20, 0x00)))
    p.set_input("oled.dc", 1)
    p.bus_transfer("spi1", B.SPI_XFER, 0, 0, bytes((0xFF,)))
    p.set_input("oled.cs", 1)
    assert lit(chip) == {(0, y) for y in range(8)}
    assert chip.display_frames()[2][-1][1] == chip.picture()
    p.set_input("oled.res", 0)
    assert sum(chip.picture()) == 0 and not chip.on


@pytest.mark.parametrize(
    "options, message",
    [
        ({"address": 0x05}, "address: expected an address from 0x08"),
        ({"bus": "spi1"}, "spi: expected true on bus spi1"),
        ({"height": 48}, "height"),
    ],
)
def test_refusals(options, message):
    with pytest.raises(PartsError, match=message):
        oled(**options)
