"""Part ``apa102_strip``: a strip of ``count`` APA102 ("DotStar") RGB LEDs on an SPI bus's
clock and data lines (no chip select: every transfer on the bus reaches it, unless its
``sck`` input is wired to the pin of its clock: then only while that pin is the SPI's).

The stream, as the datasheet frames it: a start frame of 32 zero bits, then a 32-bit frame
per LED, its first byte 0b111 and a 5-bit global brightness, then blue, green, red; then an
end frame (ones or zeros, enough clocks to push the data down the strip). The first LED
keeps the first frame after a start frame, the next LED the next, and so on (frames past the
last LED leave the strip: an end frame of ones is one of them). Four zero bytes in a row are
a start frame wherever they come (an LED frame holds three at most), so the frames may be
split over any number of transfers. A byte where an LED frame should start whose top three
bits are not 0b111 (other than a zero) is a framing fault: counted (``<name>_faults``),
skipped.

Each LED's colour is an output, ``<name>.led<i>``, ``0xRRGGBB`` as sent, and its global
brightness ``<name>.level<i>`` (0-31), from the end of the transfer that completed its frame
(one change per transfer that changes it), drawn by the report as the ``ws2812_strip``'s are.

Not modelled: ``NOT_MODELLED`` (docs/parts.md)."""

from sim_plant.buses import NEVER_US, BusDevice, BusName, Change
from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.option_table import Num


class Apa102Strip(BusDevice):
    FIXED_STATE = (*BusDevice.FIXED_STATE, "count")

    def __init__(self, name: str, bus: str, count: int):
        super().__init__(name, bus, None)
        self.count = count
        self.outputs = {f"{name}.led{i}": "u16" for i in range(count)} | {
            f"{name}.level{i}": "u16" for i in range(count)
        }
        self.frame = []  # the LED frame's bytes so far
        self.index = count  # the next LED frame's LED (count: none before a start frame)
        self.zeros = 0  # zero bytes in a row
        self.got = {}  # led -> (colour, level) of frames completed in this transfer
        self.shown = [(0, 0)] * count
        self.faults = 0
        self.frames = 0
        self.tie_cs_low()  # (no chip select: the strip hears every transfer on its bus)

    def initial_outputs(self) -> dict:
        return dict.fromkeys(self.outputs, 0)

    def exchange(self, t_us, byte):
        self.zeros = self.zeros + 1 if byte == 0 else 0
        if self.zeros == 4:  # a start frame
            self.frame, self.index = [], 0
            return 0xFF
        if not self.frame:
            if byte == 0:
                return 0xFF
            if byte & 0xE0 != 0xE0:
                self.faults += 1
                return 0xFF
        self.frame.append(byte)
        if len(self.frame) == 4:
            level, blue, green, red = self.frame
            if self.index < self.count:
                self.got[self.index] = (red << 16 | green << 8 | blue, level & 0x1F)
                self.frames += 1
            self.index += 1
            self.frame = []
        return 0xFF  # (nothing drives MISO)

    def transferred(self, t_us):
        if self.got:
            self.next_us = t_us

    def fire(self, t_us, plant, out) -> None:
        for i, (colour, level) in sorted(self.got.items()):
            was_colour, was_level = self.shown[i]
            if colour != was_colour:
                out.append(Change(t_us, f"{self.label}.led{i}", colour))
            if level != was_level:
                out.append(Change(t_us, f"{self.label}.level{i}", level))
            self.shown[i] = (colour, level)
        self.got = {}
        self.next_us = NEVER_US

    def truth(self, t_us, plant) -> dict:
        return {
            f"{self.label}_lit": sum(1 for colour, level in self.shown if colour and level),
            f"{self.label}_faults": self.faults,
            f"{self.label}_frames": self.frames,
        }


class Apa102StripPart(PartType):
    kind = "apa102_strip"
    MODELLED_FEATURES = (
        "the start frame, 32-bit LED frames (brightness, blue, green, red) split over any transfers, frames "
        "past the last LED",
        "framing faults counted",
        "each LED's colour and brightness as outputs",
    )
    NOT_MODELLED = (
        "the half clock of delay per LED (a frame shows once it is in, without the end frame's extra clocks)",
        "the brightness as a PWM of its own",
        "the SK9822's latch at the start frame",
    )
    doc = "A strip of APA102 (DotStar) RGB LEDs on an SPI bus: colours and brightness as outputs, framing checked."
    OPTIONS = (
        Opt("bus", BusName(), "spi0", "the SPI bus whose clock and data lines it is on, as the firmware creates it"),
        Opt("count", Num("LEDs", 1, 256, whole=True), 8, "how many LEDs"),
    )
    SIGNALS = (
        Sig("led<i>", "out", "u16", "LED i's colour, 0xRRGGBB, as its last frame sent it (led0, led1, ...)"),
        Sig("level<i>", "out", "u16", "LED i's global brightness, 0-31, from the same frame"),
        Sig(
            "sck",
            "in",
            "level",
            "the pin of its clock: wired, a transfer reaches the strip only while that pin is the SPI's (rp2:"
            " FUNCSEL SPI, by SPI(..., sck=), Pin.ALT alt=1 or mem32), as a kit's LEDs share MOSI with its"
            " display; not wired, every transfer on its bus does",
        ),
    )
    TRUTH = ("{name}_lit", "{name}_faults", "{name}_frames")
    VIEWS = (
        View("strip", "each LED's colour over time, a row each (the report draws the colours)", signals=("led<i>",)),
    )
    on_bus = True

    def check(self) -> None:
        if not self.options["bus"].startswith("spi"):
            raise ValueError(
                f"bus: expected an SPI bus (the APA102 has a clock and a data line), got {self.options['bus']}"
            )

    def signals(self) -> dict[str, tuple[str, str]]:
        n = self.options["count"]
        leds = {f"{self.name}.{s}{i}": ("out", "u16") for s in ("led", "level") for i in range(n)}
        return {**leds, f"{self.name}.sck": ("in", "level")}

    def add(self, build: Build) -> None:
        build.parts.append(Apa102Strip(self.name, self.options["bus"], self.options["count"]))
