"""Part ``ssd1306``: a Solomon SSD1306-class monochrome OLED controller with its panel,
128 x 64 or 128 x 32 pixels, on I2C (address 0x3C, or 0x3D by its SA0 pin) or 4-wire SPI
(its ``cs``, ``dc`` and ``res`` inputs, wired to pins the firmware drives).

I2C: after the address, a control byte (bit 7 Co, bit 6 D/C#): with Co = 0 every byte
after it is a command (D/C# = 0) or display data (1); with Co = 1 one byte follows, then
another control byte. SPI: while ``cs`` is low (or tied low: ``cs = "low"``), over any
number of transfers, each byte is a command while ``dc`` is low, data while high;
``res`` low resets the controller (its registers: the display off, page addressing), as
the pin does. A read (I2C) gives the status byte: bit 6 set while the display is off.

Commands decoded, with their argument bytes: the display on/off (0xAE/0xAF), entire
display on (0xA4/0xA5), inverse (0xA6/0xA7), contrast (0x81), the memory addressing mode
(0x20: horizontal, vertical, page), the column and page address ranges (0x21, 0x22), the
page mode's start column (0x00-0x1F) and page (0xB0-0xB7), the start line (0x40-0x7F),
segment remap (0xA0/0xA1), COM scan direction (0xC0/0xC8), the multiplex ratio (0xA8);
taken with their arguments and stored, not acted on: display offset, COM pins, clock,
pre-charge, VCOMH, charge pump, scrolling (0x26-0x2F, 0xA3: the picture does not scroll).

The picture is what the glass shows: the RAM's rows from the start line (through the
multiplex ratio), mirrored unless the segments are remapped (0xA1) and upside down unless
the COM scan is remapped (0xC8) (a module's usual set-up, which the published driver
sends, shows the RAM upright), inverted, all lit, or dark while the display is off. Each
distinct picture is kept with its time (the last ``max_frames``; after that the last one
is replaced) at the end of the transfer that made it (chip select held low or not): the
trace folder has the last as ``<name>.png`` and all as ``<name>.gif`` (``host/artefacts/pictures.py``).

Not modelled: ``NOT_MODELLED`` (docs/parts.md)."""

from sim_plant.buses import BusDevice, BusName, check_placement, chip_select
from sim_plant.catalogue.base import CS_OPTION, CS_SIGNAL, SCK_SIGNAL, Build, Opt, PartType, Sig
from sim_plant.option_table import Flag, Num, OneOf

WIDTH = 128
ARGS = {0x81: 1, 0x20: 1, 0x21: 2, 0x22: 2, 0xA8: 1, 0xD3: 1, 0xDA: 1, 0xD5: 1, 0xD9: 1, 0xDB: 1, 0x8D: 1}
ARGS |= {0x26: 6, 0x27: 6, 0x29: 5, 0x2A: 5, 0xA3: 2}
HORIZONTAL, VERTICAL, PAGE = 0, 1, 2


def keep_frame(chip, t_us: int) -> None:
    """A display chip's picture kept at ``t_us`` if it ``changed`` since the last and differs
    from it: the last ``max_frames`` distinct ones in ``frames``, the last replaced after that
    (the SSD1306's and SH1106's, the HT16K33's)."""
    if not chip.changed:
        return
    chip.changed = False
    now = chip.picture()
    frames = chip.frames
    if frames and frames[-1][1] == now:
        return
    if len(frames) >= chip.max_frames:
        frames[-1] = (t_us, now)
    else:
        frames.append((t_us, now))


class Ssd1306Chip(BusDevice):
    ARGS = ARGS  # command -> its argument bytes
    FIXED_STATE = (*BusDevice.FIXED_STATE, "height", "max_frames", "dc_signal", "res_signal")

    def __init__(self, name, bus, address, height: int, max_frames: int):
        super().__init__(name, bus, address)
        self.height = height
        self.max_frames = max_frames
        self.dc_signal = f"{name}.dc" if address is None else None
        self.res_signal = f"{name}.res" if address is None else None
        if address is None:
            self.inputs = {**self.inputs, self.dc_signal: "level", self.res_signal: "level"}
        self.ram = [0] * (WIDTH * 8)  # page-major: ram[page * 128 + column], bit n = row page * 8 + n
        self.frames: list = []  # (t_us, the picture as bytes: a row of 128 pixels a 128-byte run, 0 or 1)
        self.dc = 0
        self.changed = False
        self.reset_registers()

    def reset_registers(self) -> None:
        self.on, self.entire, self.inverse, self.contrast = False, False, False, 0x7F
        self.mode, self.col_range, self.page_range = PAGE, (0, WIDTH - 1), (0, 7)
        self.col, self.page = 0, 0
        self.start_line, self.seg_remap, self.com_remap, self.mux = 0, False, False, 63
        self.command: list = []  # a command waiting for its arguments
        self.control, self.single = None, False  # (I2C) the control byte's D/C#, Co
        self.changed = True

    # -- the buses --------------------------------------------------------------------

    def set_input(self, name, value, t_us, plant):
        if name == self.dc_signal:
            self.dc = 1 if value else 0
            return False
        if name == self.res_signal:
            if not value:
                self.reset_registers()
                self._frame(t_us)
            return False
        return super().set_input(name, value, t_us, plant)

    def begin(self, t_us, reading):
        self.control, self.single = None, False

    def write(self, t_us, byte):
        if self.control is None:
            self.control, self.single = byte >> 6 & 1, bool(byte & 0x80)
            return True
        self._byte(byte, self.control)
        if self.single:
            self.control = None
        return True

    def read(self, t_us):
        return 0x06 | (0x00 if self.on else 0x40)

    def end(self, t_us):
        self._frame(t_us)

    def exchange(self, t_us, byte):
        self._byte(byte, self.dc)
        return 0xFF  # (write-only: nothing drives MISO)

    def transferred(self, t_us):
        self._frame(t_us)  # (the glass shows the RAM as it is, chip select low or not)

    def deselect(self, t_us):
        self._frame(t_us)

    # -- the controller ---------------------------------------------------------------

    def _byte(self, byte: int, data: int) -> None:
        if data:
            self._data(byte)
            return
        self.command.append(byte)
        if len(self.command) > self.ARGS.get(self.command[0], 0):
            self._command(self.command)
            self.command = []

    def _command(self, c: list) -> None:  # noqa: C901 (a command table)
        op = c[0]
        self.changed = True
        if op in (0xAE, 0xAF):
            self.on = op == 0xAF
        elif op in (0xA4, 0xA5):
            self.entire = op == 0xA5
        elif op in (0xA6, 0xA7):
            self.inverse = op == 0xA7
        elif op == 0x81:
            self.contrast = c[1]
        elif op == 0x20:
            self.mode = c[1] & 0x03 if c[1] & 0x03 != 3 else PAGE
        elif op == 0x21:
            self.col_range = (c[1] & 0x7F, c[2] & 0x7F)
            self.col = self.col_range[0]
        elif op == 0x22:
            self.page_range = (c[1] & 0x07, c[2] & 0x07)
            self.page = self.page_range[0]
        elif op < 0x10:
            self.col = self.col & 0xF0 | op
        elif op < 0x20:
            self.col = self.col & 0x0F | (op & 0x07) << 4
        elif 0xB0 <= op <= 0xB7:
            self.page = op & 0x07
        elif 0x40 <= op <= 0x7F:
            self.start_line = op & 0x3F
        elif op in (0xA0, 0xA1):
            self.seg_remap = op == 0xA1
        elif op in (0xC0, 0xC8):
            self.com_remap = op == 0xC8
        elif op == 0xA8:
            self.mux = max(15, c[1] & 0x3F)

    def _data(self, byte: int) -> None:
        self.ram[self.page * WIDTH + self.col] = byte
        self.changed = True
        (c0, c1), (p0, p1) = self.col_range, self.page_range
        if self.mode == PAGE:
            self.col = (self.col + 1) % WIDTH
        elif self.mode == HORIZONTAL:
            if self.col >= c1:
                self.col = c0
                self.page = p0 if self.page >= p1 else self.page + 1
            else:
                self.col += 1
        elif self.page >= p1:
            self.page = p0
            self.col = c0 if self.col >= c1 else self.col + 1
        else:
            self.page += 1

    # -- the glass --------------------------------------------------------------------

    def picture(self) -> bytes:
        """What the glass shows: ``height`` rows of 128 pixels, a byte each (1: lit)."""
        rows = []
        for y in range(self.height):
            com = self.height - 1 - y if not self.com_remap else y
            if not self.on or com > self.mux:
                rows.append(bytes(WIDTH))
                continue
            if self.entire:
                rows.append(b"\x01" * WIDTH)
                continue
            rows.append(self._glass_row((com + self.start_line) % 64))
        return b"".join(rows)

    def _glass_row(self, line: int) -> bytes:
        """RAM line ``line`` as the glass shows it: 128 pixels left to right."""
        base, bit = (line >> 3) * WIDTH, line & 7
        row = bytes((self.ram[base + x] >> bit & 1) ^ self.inverse for x in range(WIDTH))
        return row if self.seg_remap else row[::-1]

    def _frame(self, t_us: int) -> None:
        keep_frame(self, t_us)

    def display_frames(self) -> tuple[int, int, list]:
        """(width, height, [(t_us, picture)]): what ``host/artefacts/pictures.py`` draws."""
        return WIDTH, self.height, list(self.frames)

    def truth(self, t_us, plant) -> dict:
        shown = self.frames[-1][1] if self.frames else bytes(WIDTH * self.height)
        return {
            f"{self.label}_lit_px": sum(shown),
            f"{self.label}_frames": len(self.frames),
            f"{self.label}_on": int(self.on),
        }


# (the options the OLED parts share: the SH1106's too)
OLED_OPTIONS = (
    Opt("bus", BusName(), "i2c0", "the bus it is on, as the firmware creates it"),
    Opt("address", Num("", 0, 127, whole=True), 0x3C, "its 7-bit I2C address (0x3C; 0x3D with SA0 high)"),
    Opt("spi", Flag(), False, "true: on an SPI bus, selected by its cs input (no address), with dc and res"),
    CS_OPTION,
)
MAX_FRAMES = Opt(
    "max_frames", Num("", 1, 10_000, whole=True), 500, "distinct pictures kept (then the last is replaced)"
)


class Ssd1306(PartType):
    kind = "ssd1306"
    MODELLED_FEATURES = (
        "I2C framing (control bytes) and 4-wire SPI (cs, dc, res)",
        "horizontal, vertical and page addressing; the column and page ranges",
        "display on/off, entire display on, inverse, start line, segment remap, COM scan direction, multiplex ratio",
        "the picture as the glass shows it, kept frame by frame (PNG and GIF in the trace folder)",
    )
    NOT_MODELLED = (
        "the COM pins configuration's effect (a 32-row panel with 0x12 would show every other row)",
        "the display offset",
        "contrast as a brightness",
        "the charge pump (the display lights without it)",
        "scrolling",
        "the 64-column panels' shift",
    )
    doc = "An SSD1306-class 128x64 or 128x32 monochrome OLED on I2C or SPI: its picture is kept in the trace folder."
    OPTIONS = (*OLED_OPTIONS, Opt("height", OneOf((64, 32)), 64, "the panel's rows (128 columns)"), MAX_FRAMES)
    SIGNALS = (
        CS_SIGNAL,
        SCK_SIGNAL,
        Sig("dc", "in", "level", "data (high) or command (low) (SPI only)", when=(("spi", (True,)),)),
        Sig("res", "in", "level", "the reset pin (SPI only: low resets the controller)", when=(("spi", (True,)),)),
    )
    TRUTH = ("{name}_lit_px", "{name}_frames", "{name}_on")
    VIEWS = ()  # (the report shows its last picture: host/report/html.py)
    on_bus = True

    def check(self) -> None:
        check_placement(self.options)

    def add(self, build: Build) -> None:
        o = self.options
        address = None if o["spi"] else o["address"]
        chip = Ssd1306Chip(self.name, o["bus"], address, o["height"], o["max_frames"])
        build.parts.append(chip_select(chip, o))
