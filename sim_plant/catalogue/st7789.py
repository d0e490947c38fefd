"""Part ``st7789``: a Sitronix ST7789 colour TFT controller with its panel (135 x 240,
240 x 240 or 240 x 320 pixels) on 4-wire SPI: its ``cs``, ``dc`` (data high, command low)
and ``res`` inputs, wired to pins the firmware drives, and ``bl``, the backlight.

While ``cs`` is low (or tied low: ``cs = "low"``), over any number of transfers, a byte
with ``dc`` low is a command, and the bytes with ``dc`` high after it its parameters (those
past what it takes are ignored, as the chip ignores them: a driver's ``b"\\x00"`` after
SLPOUT); ``res`` low resets the controller, as the pin does (SWRESET, 0x01, too): asleep,
the display off, no inversion, MADCTL 0, the window the whole memory. The frame memory,
240 columns by 320 rows of RGB565 (kept big-endian, as the bytes come), is not cleared.

Commands acted on: SLPIN/SLPOUT (0x10/0x11), NORON (0x13, normal mode: the partial mode's
PTLON, 0x12, is stored, not acted on), INVOFF/INVON (0x20/0x21), DISPOFF/DISPON
(0x28/0x29), CASET and RASET (0x2A/0x2B: the window's start and end column and row, 16
bits each, big-endian), RAMWR (0x2C: from the window's start, two bytes a pixel, the column
moving on to the window's end, then the next row; past the last row, back to the first),
RAMWRC (0x3C: on from where the last write stopped), MADCTL (0x36: MY 0x80, MX 0x40, MV
0x20, BGR 0x08), COLMOD (0x3A, stored: 0x55 and 0x05 are 16 bits a pixel). Where a pixel
lands in memory (``place``): the column counter is the memory's column and the row counter
its row, exchanged with MV; then MX mirrors the memory's column (239 - c) and MY its row
(319 - r). So the drivers' offsets land on the glass: russhughes' ``st7789py`` (its
rotation tables: the 135 x 240 panel at 52, 40 portrait, 40, 53 with MX|MV, 53, 40 with
MY|MX, 40, 52 with MY|MV; the 240 x 240 one at 0, 0 and, upside down, 0, 80 and 80, 0) and
Waveshare's Pico-Go demo (MADCTL 0x70, columns 40 to 279, rows 53 to 187).

The glass: the panel's area of the memory (135 x 240 at memory columns 52 to 186 and rows
40 to 279; 240 x 240 at 0, 0; 240 x 320 all of it), as the panel scans it (its first row at
the top), turned clockwise by ``turn_deg`` as it is mounted (the Pico-Go's 240 x 135: 270,
as its demo draws its text upright). Black while asleep, with the display off or the
backlight dark (``bl`` low; not wired: lit). An IPS glass (``ips = true``, the 1.14" and
1.3" panels, which both drivers send INVON for) shows the colours as written with the
inversion on and inverted with it off; ``ips = false`` the other way round. The glass's
subpixels in ``glass_order``: ``"rgb"`` shows the red field red while MADCTL's BGR bit is
clear (the Pico-Go's, by its demo's colour names), ``"bgr"`` while it is set.

Each distinct picture is kept with its time (the last ``max_frames``; after that the last
one is replaced) at the end of the transfer that made it, as the ``ssd1306`` part's are: the
trace folder has the last as ``<name>.png`` and all as ``<name>.gif``
(``host/artefacts/pictures.py``), in colour. Not modelled: ``NOT_MODELLED``
(docs/parts.md)."""

from dataclasses import replace

import numpy as np

from sim_plant.buses import BusDevice, BusName, chip_select
from sim_plant.catalogue.base import CS_OPTION, CS_SIGNAL, SCK_SIGNAL, Build, Opt, PartType, Sig
from sim_plant.catalogue.ssd1306 import MAX_FRAMES, keep_frame
from sim_plant.option_table import Flag, OneOf

COLUMNS, ROWS = 240, 320  # the frame memory
PANELS = {"135x240": (135, 240, 52, 40), "240x240": (240, 240, 0, 0), "240x320": (240, 320, 0, 0)}  # w, h, x0, y0
ARGS = {0x2A: 4, 0x2B: 4, 0x36: 1, 0x3A: 1}  # the commands acted on that take parameters
MY, MX, MV, BGR = 0x80, 0x40, 0x20, 0x08
RAMWR, RAMWRC = 0x2C, 0x3C


class St7789Chip(BusDevice):
    FIXED_STATE = (*BusDevice.FIXED_STATE, "panel", "turn_deg", "ips", "bgr_glass", "max_frames")
    FIXED_STATE += ("dc_signal", "res_signal", "bl_signal")

    def __init__(self, name, bus, panel: str, turn_deg: int, ips: bool, glass_order: str, max_frames: int):
        super().__init__(name, bus, None)
        self.panel, self.turn_deg, self.ips = panel, turn_deg, ips
        self.bgr_glass = glass_order == "bgr"
        self.max_frames = max_frames
        self.dc_signal, self.res_signal, self.bl_signal = f"{name}.dc", f"{name}.res", f"{name}.bl"
        self.inputs = {**self.inputs, self.dc_signal: "level", self.res_signal: "level", self.bl_signal: "level"}
        self.ram = np.zeros(COLUMNS * ROWS * 2, np.uint8)  # [(row * 240 + column) * 2]: RGB565, big-endian
        # (an array: a plant's snapshot copies it, docs/clock.md's rewind puts it back)
        self.frames: list = []  # (t_us, the picture: RGB565 big-endian, rows of the glass top first)
        self.dc, self.lit = 0, True
        self.changed = False
        self.reset_registers()

    def reset_registers(self) -> None:
        self.awake, self.on, self.inverted, self.partial = False, False, False, False
        self.madctl, self.colmod = 0, 0x66
        self.cols, self.rows = (0, COLUMNS - 1), (0, ROWS - 1)
        self.command, self.params = None, []  # the last command, its parameters so far
        self.col, self.row, self.high = 0, 0, None  # the write's counters; a pixel's first byte
        self.changed = True

    # -- the bus ----------------------------------------------------------------------

    def set_input(self, name, value, t_us, plant):
        if name == self.dc_signal:
            self.dc = 1 if value else 0
            return False
        if name == self.res_signal:
            if not value:
                self.reset_registers()
                keep_frame(self, t_us)
            return False
        if name == self.bl_signal:
            self.changed = self.changed or self.lit != bool(value)
            self.lit = bool(value)
            keep_frame(self, t_us)
            return False
        return super().set_input(name, value, t_us, plant)

    def exchange(self, t_us, byte):
        if not self.dc:
            self._command(byte)
        elif self.command in (RAMWR, RAMWRC):
            self._pixel_byte(byte)
        else:
            self.params.append(byte)
            if len(self.params) == ARGS.get(self.command, -1):
                self._parameters(self.command, self.params)
        return 0xFF  # (write-only here: MISO is not modelled)

    def transferred(self, t_us):
        keep_frame(self, t_us)  # (the glass shows the memory as it is, chip select low or not)

    def deselect(self, t_us):
        keep_frame(self, t_us)

    # -- the controller ---------------------------------------------------------------

    def _command(self, op: int) -> None:  # noqa: C901 (a command table)
        self.command, self.params, self.high = op, [], None
        if op == 0x01:
            self.reset_registers()
        elif op in (0x10, 0x11):
            self.awake = op == 0x11
        elif op in (0x12, 0x13):
            self.partial = op == 0x12
        elif op in (0x20, 0x21):
            self.inverted = op == 0x21
        elif op in (0x28, 0x29):
            self.on = op == 0x29
        elif op == RAMWR:
            self.col, self.row = self.cols[0], self.rows[0]
        else:
            return
        self.changed = True

    def _parameters(self, op: int, p: list) -> None:
        if op == 0x2A:
            self.cols = (p[0] << 8 | p[1], p[2] << 8 | p[3])
        elif op == 0x2B:
            self.rows = (p[0] << 8 | p[1], p[2] << 8 | p[3])
        elif op == 0x36:
            self.madctl = p[0]
            self.changed = True
        elif op == 0x3A:
            self.colmod = p[0]

    def place(self, col: int, row: int) -> int | None:
        """The memory's byte index of the pixel the counters (``col``, ``row``) address
        under MADCTL, or None off the memory."""
        m = self.madctl
        c, r = (row, col) if m & MV else (col, row)
        if m & MX:
            c = COLUMNS - 1 - c
        if m & MY:
            r = ROWS - 1 - r
        if 0 <= c < COLUMNS and 0 <= r < ROWS:
            return (r * COLUMNS + c) * 2
        return None

    def _pixel_byte(self, byte: int) -> None:
        if self.high is None:
            self.high = byte
            return
        at = self.place(self.col, self.row)
        if at is not None:
            self.ram[at] = self.high
            self.ram[at + 1] = byte
            self.changed = True
        self.high = None
        (c0, c1), (r0, r1) = self.cols, self.rows
        if self.col < c1:
            self.col += 1
        else:
            self.col = c0
            self.row = self.row + 1 if self.row < r1 else r0

    # -- the glass --------------------------------------------------------------------

    def size(self) -> tuple[int, int]:
        """The picture's (width, height): the panel's, exchanged when turned by 90 or 270."""
        w, h, _x0, _y0 = PANELS[self.panel]
        return (h, w) if self.turn_deg % 180 else (w, h)

    def picture(self) -> bytes:
        """What the glass shows: RGB565 big-endian, two bytes a pixel, rows of ``size()``."""
        w, h, x0, y0 = PANELS[self.panel]
        if not (self.awake and self.on and self.lit):
            return bytes(w * h * 2)
        shown = self.ram.reshape(ROWS, COLUMNS, 2)[y0 : y0 + h, x0 : x0 + w]  # (rows, columns, the two bytes)
        if self.inverted != self.ips:
            shown = 255 - shown
        if bool(self.madctl & BGR) != self.bgr_glass:
            shown = _swap_red_blue(shown)
        return np.ascontiguousarray(np.rot90(shown, -self.turn_deg // 90)).tobytes()

    def display_frames(self) -> tuple[int, int, list]:
        """(width, height, [(t_us, picture)]): what ``host/artefacts/pictures.py`` draws."""
        return (*self.size(), list(self.frames))

    def truth(self, t_us, plant) -> dict:
        w, h = self.size()
        shown = self.frames[-1][1] if self.frames else bytes(w * h * 2)
        return {
            f"{self.label}_lit_px": w * h - memoryview(shown).cast("H").tolist().count(0),
            f"{self.label}_frames": len(self.frames),
            f"{self.label}_on": int(self.awake and self.on and self.lit),
        }


def _swap_red_blue(shown: np.ndarray) -> np.ndarray:
    """Pixels (their two bytes, big-endian, on the last axis) with red and blue exchanged."""
    v = shown[..., 0].astype(np.uint16) << 8 | shown[..., 1]
    v = (v & 0x1F) << 11 | v & 0x07E0 | v >> 11
    return np.stack(((v >> 8).astype(np.uint8), (v & 0xFF).astype(np.uint8)), axis=-1)


class St7789(PartType):
    kind = "st7789"
    MODELLED_FEATURES = (
        "4-wire SPI: commands and parameters by dc over any transfers; res and SWRESET",
        "the 240 x 320 RGB565 frame memory, the CASET/RASET window, RAMWR and RAMWRC with their counters",
        "MADCTL's MY, MX, MV and BGR: where a pixel lands, so the drivers' column and row offsets fit the panel",
        "sleep, display on/off, inversion (an IPS glass's), the backlight, the glass's colour order",
        "135 x 240, 240 x 240 and 240 x 320 panels, turned as mounted; the picture kept frame by frame (PNG, GIF)",
    )
    NOT_MODELLED = (
        "pixel formats other than 16 bits (COLMOD is stored; every pixel is taken as two bytes)",
        "reads (RDDID, RAMRD: MISO is not driven)",
        "partial mode and vertical scrolling (PTLON, VSCRDEF, VSCSAD: the picture does not scroll)",
        "MADCTL's ML and MH (refresh order: no effect on a still picture)",
        "the waits the datasheet asks for (120 ms after reset and SLPOUT): a command is taken at once",
        "gamma, porch, power and VCOM settings (taken and ignored)",
        "the backlight's brightness (PWM on bl: lit while high)",
    )
    doc = "A Sitronix ST7789 colour TFT (135x240, 240x240, 240x320) on SPI: its picture is kept in the trace folder."
    OPTIONS = (
        Opt("bus", BusName(), "spi0", "the SPI bus it is on, as the firmware creates it"),
        CS_OPTION,
        Opt("panel", OneOf(tuple(PANELS)), "135x240", "the glass: columns x rows as it scans (its area of the memory)"),
        Opt("turn_deg", OneOf((0, 90, 180, 270)), 0, "the glass as mounted: its picture turned clockwise by this"),
        Opt("ips", Flag(), True, "an IPS glass: true colours with the inversion on (INVON), inverted with it off"),
        Opt("glass_order", OneOf(("rgb", "bgr")), "rgb", 'its subpixels: "rgb" shows red red with MADCTL BGR clear'),
        MAX_FRAMES,
    )
    SIGNALS = (
        replace(CS_SIGNAL, doc="the chip select (low selects it)", when=(("cs", ("pin",)),)),
        replace(SCK_SIGNAL, doc=SCK_SIGNAL.doc.replace(" (SPI only)", ""), when=()),
        Sig("dc", "in", "level", "data (high) or command (low)"),
        Sig("res", "in", "level", "the reset pin (low resets the controller; not wired: never)"),
        Sig("bl", "in", "level", "the backlight (high: lit; not wired: lit)"),
    )
    TRUTH = ("{name}_lit_px", "{name}_frames", "{name}_on")
    VIEWS = ()  # (the report shows its last picture: host/report/html.py)
    on_bus = True

    def check(self) -> None:
        if not self.options["bus"].startswith("spi"):
            raise ValueError(f"bus: expected an SPI bus (the ST7789 part is on SPI only), got {self.options['bus']}")

    def add(self, build: Build) -> None:
        o = self.options
        chip = St7789Chip(self.name, o["bus"], o["panel"], o["turn_deg"], o["ips"], o["glass_order"], o["max_frames"])
        build.parts.append(chip_select(chip, o))
