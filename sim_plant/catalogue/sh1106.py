"""Part ``sh1106``: a Sino Wealth SH1106 monochrome OLED controller with a 128 x 64 panel,
on I2C (address 0x3C, or 0x3D by its SA0 pin) or 4-wire SPI (its ``cs``, ``dc`` and ``res``
inputs, wired to pins the firmware drives), framed on the bus as the ``ssd1306`` part is
(the control byte on I2C, D/C on SPI; ``res`` low resets the controller).

Its RAM is 132 columns by 8 pages; the 128-pixel glass sits on segments 2 to 129, so a
picture drawn at RAM column 2 onward fills it (what the drivers' column offset of 2 is
for). Only page addressing: the page (0xB0-0xB7), the column's low nibble (0x00-0x0F) and
high nibble (0x10-0x1F; column 0-131), the column moving on with each data byte and
stopping at 131; no horizontal or vertical mode (the SSD1306's 0x20, 0x21, 0x22 are not
commands here: 0x20-0x22 are taken as the start of no command and ignored).

Commands decoded, with their argument bytes: the display on/off (0xAE/0xAF), entire
display on (0xA4/0xA5), inverse (0xA6/0xA7), contrast (0x81), the start line (0x40-0x7F),
segment remap (0xA0/0xA1), COM scan direction (0xC0/0xC8), the multiplex ratio (0xA8);
taken with their arguments and stored, not acted on: display offset (0xD3), the clock
(0xD5), pre-charge (0xD9), COM pins (0xDA), VCOM (0xDB), the DC-DC converter (0xAD), the
pump voltage (0x30-0x33), read-modify-write (0xE0/0xEE), NOP (0xE3).

The picture, its frames and the trace folder's PNG and GIF are as the ``ssd1306`` part's:
segment remap (0xA1) shows glass pixel x from RAM column x + 2, no remap from column
129 - x, mirrored. Not modelled: ``NOT_MODELLED`` (docs/parts.md)."""

from sim_plant.buses import chip_select
from sim_plant.catalogue.base import Build
from sim_plant.catalogue.ssd1306 import MAX_FRAMES, OLED_OPTIONS, WIDTH, Ssd1306, Ssd1306Chip

RAM_WIDTH = 132
OFFSET = 2  # the glass's first segment
ARGS = {0x81: 1, 0xA8: 1, 0xD3: 1, 0xD5: 1, 0xD9: 1, 0xDA: 1, 0xDB: 1, 0xAD: 1}


class Sh1106Chip(Ssd1306Chip):
    ARGS = ARGS

    def __init__(self, name, bus, address, max_frames: int):
        super().__init__(name, bus, address, 64, max_frames)
        self.ram = [0] * (RAM_WIDTH * 8)  # page-major: ram[page * 132 + column]

    def _command(self, c: list) -> None:
        op = c[0]
        if op < 0x10:
            self.col = self.col & 0xF0 | op
        elif op < 0x20:
            self.col = min(RAM_WIDTH - 1, self.col & 0x0F | (op & 0x0F) << 4)
        elif op < 0x40 or op in (0xAD, 0xD3, 0xD5, 0xD9, 0xDA, 0xDB, 0xE0, 0xEE, 0xE3):
            return  # (pump voltage, stored settings: no effect on the picture)
        else:
            super()._command(c)  # (the rest are the SSD1306's, same codes and meaning)
        self.changed = True

    def _data(self, byte: int) -> None:
        self.ram[self.page * RAM_WIDTH + self.col] = byte
        self.changed = True
        self.col = min(RAM_WIDTH - 1, self.col + 1)

    def _glass_row(self, line: int) -> bytes:
        """RAM line ``line`` on the glass: columns 2 to 129, or 129 down to 2 without segment remap."""
        base, bit = (line >> 3) * RAM_WIDTH, line & 7
        cols = range(OFFSET, OFFSET + WIDTH) if self.seg_remap else range(RAM_WIDTH - 1 - OFFSET, OFFSET - 1, -1)
        return bytes((self.ram[base + x] >> bit & 1) ^ self.inverse for x in cols)


class Sh1106(Ssd1306):  # (its signals, truth and check: the SSD1306's)
    kind = "sh1106"
    MODELLED_FEATURES = (
        "I2C framing (control bytes) and 4-wire SPI (cs, dc, res), as the ssd1306 part's",
        "a 132-column RAM, the glass on columns 2 to 129; page addressing only",
        "display on/off, entire display on, inverse, start line, segment remap, COM scan direction, multiplex ratio",
        "the picture as the glass shows it, kept frame by frame",
    )
    NOT_MODELLED = (
        "the display offset",
        "contrast as a brightness",
        "the DC-DC converter (the display lights without it)",
        "read-modify-write's column that does not move",
    )
    doc = "An SH1106 128x64 monochrome OLED (132-column RAM) on I2C or SPI: its picture is kept in the trace folder."
    OPTIONS = (*OLED_OPTIONS, MAX_FRAMES)

    def add(self, build: Build) -> None:
        o = self.options
        address = None if o["spi"] else o["address"]
        build.parts.append(chip_select(Sh1106Chip(self.name, o["bus"], address, o["max_frames"]), o))
