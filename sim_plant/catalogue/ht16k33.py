"""Part ``ht16k33``: a Holtek HT16K33 LED controller on I2C (address 0x70 to 0x77 by its
A0..A2 pins; 0x70 by default) driving an 8 x 8 LED matrix, as on the Keyestudio
Beetlebot's matrix module.

I2C, after the address, a command byte: 0x0n with bytes after it writes the display RAM
(16 bytes, the address pointer n, auto-incrementing and wrapping at 16); 0x20/0x21 the
system oscillator off/on (standby/normal); 0x80..0x87 the display setup (bit 0 on, bits 2:1
the blink rate); 0xE0..0xEF the dimming (1/16 to 16/16 duty); 0xA0..0xA3 ROW/INT set
(stored). Each command is a transfer of its own, as the datasheet's timing diagrams write
them. A read gives the RAM from the pointer (the key RAM is not modelled).

The matrix: COM n (RAM byte 2n) is the n-th row from the top, ROW r (bit r of that byte)
the r-th column from the left, as the icons of Keyestudio's Beetlebot tutorials show on its
module (a smiley, ``b"\x00\x66\x00\x00\x18\x42\x3c\x00"``, upright; the turns' arrows,
``b"\x48\x24..."`` pointing left): their driver's docstring (``ht16k33matrix.py``,
``set_icon``: "columns 0 through 7, left to right") is the Adafruit backpack's, not the
module's. It is lit while the oscillator runs and the display is on. Each
distinct picture is kept with its time (the last ``max_frames``; after that the last one is
replaced): the trace folder has the last as ``<name>.png`` and all as ``<name>.gif``.

Not modelled: ``NOT_MODELLED`` (docs/parts.md)."""

from sim_plant.buses import BusDevice, BusName, check_placement
from sim_plant.catalogue.base import Build, Opt, PartType
from sim_plant.catalogue.ssd1306 import MAX_FRAMES, keep_frame
from sim_plant.option_table import Num

SIZE = 8
RAM = 16


class Ht16k33Chip(BusDevice):
    FIXED_STATE = (*BusDevice.FIXED_STATE, "max_frames")

    def __init__(self, name, bus, address, max_frames: int):
        super().__init__(name, bus, address)
        self.max_frames = max_frames
        self.ram = [0] * RAM
        self.pointer = 0
        self.oscillator, self.on, self.blink, self.dimming, self.row_int = False, False, 0, 15, 0
        self.first = True  # the transfer's next byte is its command
        self.writing = False  # the command was a RAM address: data bytes follow
        self.changed = True
        self.frames: list = []  # (t_us, the picture: 8 rows of 8 pixels, top row first, a byte each)

    def begin(self, t_us, reading):
        self.first, self.writing = True, False

    def write(self, t_us, byte):
        if self.first:
            self.first = False
            self._command(byte)
            return True
        if self.writing:
            self.ram[self.pointer] = byte
            self.pointer = (self.pointer + 1) % RAM
            self.changed = True
        return True

    def read(self, t_us):
        byte = self.ram[self.pointer]
        self.pointer = (self.pointer + 1) % RAM
        return byte

    def end(self, t_us):
        self._frame(t_us)

    def _command(self, byte: int) -> None:
        high = byte & 0xF0
        if high == 0x00:
            self.pointer, self.writing = byte & 0x0F, True
        elif high == 0x20:
            self.oscillator = bool(byte & 1)
        elif high == 0x80:
            self.on, self.blink = bool(byte & 1), byte >> 1 & 3
        elif high == 0xE0:
            self.dimming = byte & 0x0F
        elif high == 0xA0:
            self.row_int = byte & 0x03
        else:
            return
        self.changed = True

    def picture(self) -> bytes:
        """What the matrix shows: 8 rows of 8 pixels, the top row first, a byte each (1: lit)."""
        if not (self.oscillator and self.on):
            return bytes(SIZE * SIZE)
        return bytes(self.ram[2 * y] >> x & 1 for y in range(SIZE) for x in range(SIZE))

    def _frame(self, t_us: int) -> None:
        keep_frame(self, t_us)

    def display_frames(self) -> tuple[int, int, list]:
        """(width, height, [(t_us, picture)]): what ``host/artefacts/pictures.py`` draws."""
        return SIZE, SIZE, list(self.frames)

    def truth(self, t_us, plant) -> dict:
        shown = self.frames[-1][1] if self.frames else bytes(SIZE * SIZE)
        return {
            f"{self.label}_lit_px": sum(shown),
            f"{self.label}_frames": len(self.frames),
            f"{self.label}_on": int(self.oscillator and self.on),
            f"{self.label}_dimming": self.dimming,
        }


class Ht16k33(PartType):
    kind = "ht16k33"
    MODELLED_FEATURES = (
        "the display RAM written from its address pointer (auto-incrementing, wrapping at 16 bytes)",
        "the oscillator (0x20/0x21), display on/off and blink setting (0x80..0x87), dimming (0xE0..0xEF)",
        "an 8 x 8 matrix, COM0..7 its rows and ROW0..7 its columns, kept frame by frame (PNG and GIF)",
    )
    NOT_MODELLED = (
        "blinking (the rate is kept, the picture does not blink)",
        "dimming as a brightness (the setting is in the truth)",
        "the key scan and its RAM, the INT output",
        "other matrix wirings (Adafruit's 8 x 8 backpack) and 16 x 8 displays",
    )
    doc = "A Holtek HT16K33 LED controller on I2C driving an 8x8 matrix: its picture is kept in the trace folder."
    OPTIONS = (
        Opt("bus", BusName(), "i2c0", "the bus it is on, as the firmware creates it"),
        Opt("address", Num("", 0x70, 0x77, whole=True), 0x70, "its 7-bit I2C address (0x70 + A2..A0)"),
        MAX_FRAMES,
    )
    SIGNALS = ()
    TRUTH = ("{name}_lit_px", "{name}_frames", "{name}_on", "{name}_dimming")
    VIEWS = ()  # (the report shows its last picture: host/report/html.py)
    on_bus = True

    def check(self) -> None:
        check_placement(self.options, i2c_only="the HT16K33")

    def add(self, build: Build) -> None:
        o = self.options
        build.parts.append(Ht16k33Chip(self.name, o["bus"], o["address"], o["max_frames"]))
