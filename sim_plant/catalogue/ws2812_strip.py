"""Part ``ws2812_strip``: a strip of ``count`` WS2812(B) RGB LEDs ("NeoPixels") on one data
pin (``<name>.din``), written by ``machine.bitstream`` / ``neopixel.NeoPixel.write``
(``docs/shim.md``, "Buses").

The strip decodes each bit as a WS2812 does: a high longer than :data:`SAMPLE_NS` is a 1.
The first LED keeps the first 24 bits (green, red, blue: the strip's order), the next LED
the next 24, and so on (bits past the last LED leave the strip). The colours show when
the line has been low for ``reset_us`` after the stream (the latch); a stream that starts
before that goes on with the same frame. Each LED's colour is an output,
``<name>.led<i>``, ``0xRRGGBB`` (in the trace and the VCD as an integer, one change per
latch that changes it).

WS2812 timing is checked: each of the stream's (high_0, low_0, high_1, low_1) against the
datasheet's (400, 850, 800, 450) ns within ``tolerance_ns`` (WS2812B: 150); a bit the
stream does not have is not checked (a PIO program's frame comes in bursts as its FIFO
fills, a burst of black all 0s). A frame (the streams between two latches:
``<name>_writes``) out of tolerance is counted in the truth (``<name>_timing_faults``) and its first problem is kept
(the part's ``timing_problem``); its bits are decoded as a chip would
(a 400 kHz tuple on this strip reads every bit as a 1: white).

Not modelled: ``NOT_MODELLED`` (docs/parts.md)."""

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.engine import Part
from sim_plant.option_table import Num
from sim_plant.plant import NEVER_US, Change

WS2812_NS = (400, 850, 800, 450)
"""The datasheet's T0H, T0L, T1H, T1L at 800 kHz (and MicroPython's ``timing=1``)."""
SAMPLE_NS = 625
"""A high longer than this reads as a 1 (between T0H and T1H, where a WS2812 samples)."""
BITS_PER_LED = 24


def timing_problem(timing_ns: tuple, tolerance_ns: float) -> str | None:
    """Why a bitstream's timing is out of the WS2812's tolerance (None: it is within). A
    None is a bit the stream does not have (a PIO burst of 0s only: its 1s unmeasured)."""
    names = ("high_0", "low_0", "high_1", "low_1")
    off = [
        f"{n} {t} ns"
        for n, t, want in zip(names, timing_ns, WS2812_NS)
        if t is not None and abs(t - want) > tolerance_ns
    ]
    if not off:
        return None
    return (
        f"bitstream timing {tuple(timing_ns)} ns: expected each within {tolerance_ns:g} ns of the WS2812's "
        f"{WS2812_NS} (high_0, low_0, high_1, low_1); out of it: {', '.join(off)}"
    )


class Ws2812Strip(Part):
    FIXED_STATE = ("inputs", "outputs", "label", "count", "reset_us", "tolerance_ns", "din")

    def __init__(self, name: str, count: int, reset_us: int, tolerance_ns: float):
        self.label = name
        self.count = count
        self.reset_us = reset_us
        self.tolerance_ns = tolerance_ns
        self.din = f"{name}.din"
        self.inputs = {self.din: "level"}
        self.outputs = {f"{name}.led{i}": "u16" for i in range(count)}
        self.frame = []  # the bits' bytes of the frame being received
        self.shown = [0] * count  # each LED's colour, 0xRRGGBB
        self.end_us = -(10**12)  # the last stream's end
        self.next_us = NEVER_US
        self.faults = 0  # frames out of tolerance
        self.frame_faulty = False
        self.streams = 0  # frames: streams after the line latched
        self.timing_problem = None

    def set_input(self, name, value, t_us, plant) -> bool:
        return False  # (a level on the pin: no stream, nothing shown)

    def initial_outputs(self) -> dict:
        return dict.fromkeys(self.outputs, 0)

    def bitstream(self, t_us: int, timing_ns: tuple, data: bytes) -> None:
        """A stream starting at ``t_us``: its bits decoded into the frame; the latch after it."""
        if t_us - self.end_us >= self.reset_us:
            self.frame = []
            self.streams += 1  # (a frame: a PIO program's comes in several bursts)
            self.frame_faulty = False
        problem = timing_problem(timing_ns, self.tolerance_ns)
        if problem:
            self.faults += not self.frame_faulty
            self.frame_faulty = True
            self.timing_problem = self.timing_problem or problem
        one_as = int(timing_ns[2] > SAMPLE_NS) if timing_ns[2] is not None else 1
        zero_as = int(timing_ns[0] > SAMPLE_NS) if timing_ns[0] is not None else 0
        total_ns = 0
        for byte in data:
            decoded = 0
            for bit in range(7, -1, -1):
                one = byte >> bit & 1
                decoded = decoded << 1 | (one_as if one else zero_as)
                total_ns += timing_ns[2] + timing_ns[3] if one else timing_ns[0] + timing_ns[1]
            self.frame.append(decoded)
        self.end_us = t_us + (total_ns + 999) // 1000
        self.next_us = self.end_us + self.reset_us

    def fire(self, t_us, plant, out) -> None:
        frame = self.frame
        for i in range(min(self.count, len(frame) // 3)):
            g, r, b = frame[3 * i : 3 * i + 3]
            colour = r << 16 | g << 8 | b
            if colour != self.shown[i]:
                self.shown[i] = colour
                out.append(Change(t_us, f"{self.label}.led{i}", colour))
        self.next_us = NEVER_US

    def truth(self, t_us, plant) -> dict:
        return {
            f"{self.label}_lit": sum(1 for c in self.shown if c),
            f"{self.label}_timing_faults": self.faults,
            f"{self.label}_writes": self.streams,
        }


class Ws2812StripPart(PartType):
    kind = "ws2812_strip"
    MODELLED_FEATURES = (
        "bits decoded as the chip does (a long high is a 1), GRB order, the latch after reset_us low",
        "the stream's timing checked against the datasheet within tolerance_ns",
    )
    NOT_MODELLED = (
        "RGBW (SK6812) strips",
        "the 400 kHz WS2811",
        "brightness per current",
        "a low inside a stream long enough to latch",
    )
    doc = "A strip of WS2812 RGB LEDs on one pin (machine.bitstream, neopixel): colours as outputs, timing checked."
    OPTIONS = (
        Opt("count", Num("LEDs", 1, 256, whole=True), 8, "how many LEDs"),
        Opt("reset_us", Num("microseconds", 6, 1_000, whole=True), 280, "the low that latches a frame (WS2812B: 280)"),
        Opt("tolerance_ns", Num("nanoseconds", 0, 1_000), 150.0, "how far a high or a low may be off the datasheet's"),
    )
    SIGNALS = (
        Sig("din", "in", "level", "the data line (a pin the firmware sends machine.bitstream on)"),
        Sig("led<i>", "out", "u16", "LED i's colour, 0xRRGGBB, from each latch (one per LED: led0, led1, ...)"),
    )
    TRUTH = ("{name}_lit", "{name}_timing_faults", "{name}_writes")
    VIEWS = (
        View("strip", "each LED's colour over time, a row each (the report draws the colours)", signals=("led<i>",)),
    )

    def signals(self) -> dict[str, tuple[str, str]]:
        signals = {f"{self.name}.din": ("in", "level")}
        signals.update({f"{self.name}.led{i}": ("out", "u16") for i in range(self.options["count"])})
        return signals

    def add(self, build: Build) -> None:
        o = self.options
        build.parts.append(Ws2812Strip(self.name, o["count"], o["reset_us"], o["tolerance_ns"]))
