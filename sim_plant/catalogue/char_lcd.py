"""Part ``char_lcd``: an HD44780 character LCD (16 x 2, 20 x 4) behind a PCF8574 I2C
backpack (address 0x27 by default), as the LCD1602 / LCD2004 I2C modules are and as
Wokwi's ``wokwi-lcd1602`` with ``pins = "i2c"`` simulates it.

Each byte written to the PCF8574 sets its eight pins: P0 RS, P1 R/W, P2 E, P3 the
backlight, P4..P7 the controller's D4..D7. The controller latches D4..D7 when E falls. At
power-on it is in 8-bit mode: each latch is a whole instruction with D0..D3 low (the
drivers' 0x3 nibbles, then 0x2, the function set that makes it 4-bit); in 4-bit mode two
latches make a byte, high nibble first. RS high: the byte is data for DDRAM (or CGRAM);
low: an instruction.

Instructions decoded: clear (0x01: DDRAM to spaces, the address to 0, increment), home
(0x02), entry mode (0x04: increment or decrement, display shift), display control (0x08:
display, cursor, blink), cursor or display shift (0x10), function set (0x20: 8 or 4 bits,
one or two lines), the CGRAM address (0x40: data then goes to the custom characters) and
the DDRAM address (0x80). DDRAM is 80 characters: with two lines 0x00..0x27 and
0x40..0x67 (the address wraps from one to the other); the glass shows ``cols`` x ``rows``
of it from rows at 0x00, 0x40, 0x14, 0x54 (a 2004's third and fourth rows continue the
first two), moved by the display shift.

The text on the glass (:meth:`CharLcdChip.lines`) is kept each time it changes, with its
time (the last ``max_screens``), at the end of the transfer that changed it. Not
modelled: reads (the busy flag: a read gives back the port's last byte, as a PCF8574's
quasi-bidirectional pins do with nothing pulling them), the instruction times (a driver
that does not wait is not caught), the 5 x 10 font, the contrast."""

from sim_plant.buses import BusDevice, BusName, check_placement
from sim_plant.catalogue.base import Build, Opt, PartType
from sim_plant.option_table import Num, OneOf

RS, RW, E, BACKLIGHT = 0x01, 0x02, 0x04, 0x08
ROW_BASES = (0x00, 0x40, 0x14, 0x54)
CUSTOM = "\u2588"  # how a custom character (codes 0..7) is shown in the text


class CharLcdChip(BusDevice):
    FIXED_STATE = (*BusDevice.FIXED_STATE, "cols", "rows", "max_screens")

    def __init__(self, name, bus, address, cols: int, rows: int, max_screens: int):
        super().__init__(name, bus, address)
        self.cols, self.rows, self.max_screens = cols, rows, max_screens
        self.port = 0
        self.eight_bit, self.high = True, None  # 4-bit mode: the high nibble waiting for its low one
        self.ddram = [0x20] * 128
        self.cgram = [0] * 64
        self.address_counter, self.in_cgram = 0, False
        self.increment, self.shift_display, self.shift = True, False, 0
        self.display_on, self.cursor_on, self.blink_on = False, False, False
        self.two_lines = False
        self.screens: list = []  # (t_us, the text: rows joined by newlines)
        self.writes = 0

    # -- the bus (the PCF8574) ---------------------------------------------------------

    def write(self, t_us, byte):
        falling = self.port & E and not byte & E
        self.port = byte
        if falling and not byte & RW:
            self._latch(byte >> 4, byte & RS)
        return True

    def read(self, t_us):
        return self.port

    def end(self, t_us):
        now = "\n".join(self.lines())
        if not self.screens or self.screens[-1][1] != now:
            if len(self.screens) >= self.max_screens:
                self.screens[-1] = (t_us, now)
            else:
                self.screens.append((t_us, now))

    # -- the controller (the HD44780) --------------------------------------------------

    def _latch(self, nibble: int, rs: int) -> None:
        if self.eight_bit:
            self._byte(nibble << 4, rs)
        elif self.high is None:
            self.high = nibble
        else:
            byte, self.high = self.high << 4 | nibble, None
            self._byte(byte, rs)

    def _byte(self, byte: int, rs: int) -> None:
        if rs:
            self._data(byte)
        else:
            self._instruction(byte)

    def _instruction(self, op: int) -> None:  # noqa: C901 (an instruction table)
        if op & 0x80:
            self.address_counter, self.in_cgram = op & 0x7F, False
        elif op & 0x40:
            self.address_counter, self.in_cgram = op & 0x3F, True
        elif op & 0x20:
            self.eight_bit, self.two_lines, self.high = bool(op & 0x10), bool(op & 0x08), None
        elif op & 0x10:
            step = 1 if op & 0x04 else -1  # right, left
            if op & 0x08:
                self.shift -= step  # the text moves right: the glass shows from one address before
            else:
                self.address_counter = self._next(self.address_counter, step)
        elif op & 0x08:
            self.display_on, self.cursor_on, self.blink_on = bool(op & 4), bool(op & 2), bool(op & 1)
        elif op & 0x04:
            self.increment, self.shift_display = bool(op & 2), bool(op & 1)
        elif op & 0x02:
            self.address_counter, self.in_cgram, self.shift = 0, False, 0
        elif op & 0x01:
            self.ddram = [0x20] * 128
            self.address_counter, self.in_cgram, self.shift, self.increment = 0, False, 0, True

    def _data(self, byte: int) -> None:
        self.writes += 1
        step = 1 if self.increment else -1
        if self.in_cgram:
            self.cgram[self.address_counter] = byte & 0x1F
            self.address_counter = (self.address_counter + step) % 64
            return
        self.ddram[self.address_counter] = byte
        self.address_counter = self._next(self.address_counter, step)
        if self.shift_display:
            self.shift += step

    def _next(self, address: int, step: int) -> int:
        """The DDRAM address after ``address`` (two lines: 0x00..0x27 and 0x40..0x67, wrapping)."""
        if not self.two_lines:
            return (address + step) % 80
        line, col = (1 if address >= 0x40 else 0), address & 0x3F
        col += step
        if col > 0x27:
            line, col = 1 - line, 0
        elif col < 0:
            line, col = 1 - line, 0x27
        return line * 0x40 + col

    # -- the glass ----------------------------------------------------------------------

    def lines(self) -> list[str]:
        """The text the glass shows, a string a row (blank while the display is off)."""
        if not self.display_on:
            return [" " * self.cols for _ in range(self.rows)]
        out = []
        for row in range(self.rows):
            base = ROW_BASES[row]
            line = base & 0x40
            chars = [self.ddram[line + ((base & 0x3F) + col + self.shift) % 40] for col in range(self.cols)]
            out.append("".join(CUSTOM if c < 8 else chr(c) if 0x20 <= c < 0x7F else "?" for c in chars))
        return out

    def truth(self, t_us, plant) -> dict:
        return {
            f"{self.label}_chars": sum(1 for row in self.lines() for c in row if c != " "),
            f"{self.label}_screens": len(self.screens),
            f"{self.label}_backlight": int(bool(self.port & BACKLIGHT)),
        }


class CharLcd(PartType):
    kind = "char_lcd"
    MODELLED_FEATURES = (
        "the PCF8574 backpack's pins, the HD44780's 8- and 4-bit modes",
        "clear, home, entry mode, display control, shift, function set, CGRAM and DDRAM addresses",
        "the text on the glass, kept each time it changes",
    )
    NOT_MODELLED = (
        "reads (the busy flag)",
        "the instruction times (a driver that does not wait is not caught)",
        "the 5 x 10 font",
        "the contrast",
    )
    doc = "An HD44780 character LCD (16x2, 20x4) on a PCF8574 I2C backpack: the text it shows."
    OPTIONS = (
        Opt("bus", BusName(), "i2c0", "the bus it is on, as the firmware creates it"),
        Opt(
            "address", Num("", 0, 127, whole=True), 0x27, "the backpack's 7-bit I2C address (0x27; 0x3F for a PCF8574A)"
        ),
        Opt("cols", OneOf((16, 20)), 16, "characters a row"),
        Opt("rows", OneOf((2, 4)), 2, "rows"),
        Opt("max_screens", Num("", 1, 10_000, whole=True), 500, "distinct texts kept (then the last is replaced)"),
    )
    SIGNALS = ()
    TRUTH = ("{name}_chars", "{name}_screens", "{name}_backlight")
    VIEWS = ()
    on_bus = True

    def check(self) -> None:
        check_placement(self.options, i2c_only=self.kind)

    def add(self, build: Build) -> None:
        o = self.options
        build.parts.append(CharLcdChip(self.name, o["bus"], o["address"], o["cols"], o["rows"], o["max_screens"]))
