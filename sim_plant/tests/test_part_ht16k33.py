"""The ht16k33 part (sim_plant/catalogue/ht16k33.py) played as the shim's BUS frames play
it: the commands a driver sends (oscillator, display on, dimming), the display RAM from its
pointer, and the 8 x 8 matrix as the Keyestudio Beetlebot's module shows it."""

from sim_plant import buses as B
from sim_plant.catalogue.assembly import assemble


def matrix(**options):
    p = assemble({"body": "bench", "parts": [{"kind": "ht16k33", "name": "matrix", **options}]})
    return p, next(d for d in p.bus_set.devices if d.label == "matrix")


def send(p, *data, address=0x70):
    return p.bus_transfer("i2c0", B.XFER, address, 0, bytes(data))[0]


def rows(chip) -> list[str]:
    picture = chip.picture()
    return ["".join(".#"[v] for v in picture[y * 8 : y * 8 + 8]) for y in range(8)]


def test_the_smiley_of_keyestudio_s_tutorial_shows_upright_once_the_oscillator_and_display_are_on():
    p, chip = matrix()
    icon = b"\x00\x66\x00\x00\x18\x42\x3c\x00"  # (Project 03's: one byte a row, bit 0 the left column)
    frame = bytes((0,)) + bytes(b for row in icon for b in (row, 0))  # (their driver's draw(): 17 bytes)
    assert send(p, *frame) == B.OK
    assert sum(chip.picture()) == 0, "dark until the oscillator runs and the display is on"
    for command in (0x21, 0x81, 0xE2):  # (power_on(), set_brightness(2): a transfer each)
        assert send(p, command) == B.OK
    assert rows(chip) == [
        "........",
        ".##..##.",
        "........",
        "........",
        "...##...",
        ".#....#.",
        "..####..",
        "........",
    ]
    truth = chip.truth(0, p)
    assert (truth["matrix_on"], truth["matrix_dimming"], truth["matrix_lit_px"]) == (1, 2, 12)


def test_the_ram_pointer_auto_increments_and_wraps_and_reads_back():
    p, chip = matrix(address=0x71)
    assert send(p, 0x0E, 0x01, 0x00, 0x80, address=0x71) == B.OK  # row 7 (RAM 14), wraps to row 0 (RAM 0)
    assert chip.ram[14] == 0x01 and chip.ram[0] == 0x80
    assert send(p, 0x0E, address=0x71) == B.OK
    assert p.bus_transfer("i2c0", B.XFER, 0x71, 3, b"")[2] == bytes((0x01, 0x00, 0x80))
    assert send(p, 0x21) == B.NACK_ADDRESS, "nothing at 0x70: its address is 0x71"
    assert send(p, 0x21, address=0x71) == B.OK and send(p, 0x80, address=0x71) == B.OK
    assert sum(chip.picture()) == 0, "display off (0x80)"
    assert send(p, 0x81, address=0x71) == B.OK
    assert rows(chip)[0] == ".......#" and rows(chip)[7] == "#......."
