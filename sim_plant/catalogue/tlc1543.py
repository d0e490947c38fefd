"""Part ``tlc1543``: a TLC1543 10-bit serial ADC (Texas Instruments, SLAS052) with
reflectance sensors on its analog inputs looking at the floor: the line sensor board of
the Waveshare Pico-Go and AlphaBot2 robots (five ITR20001 sensors on channels 0..4).

The chip is read over four lines the board drives or reads: chip select ``<name>.cs``,
I/O clock ``<name>.clk``, address in ``<name>.addr`` and data out ``<name>.dout``. As the
datasheet's timing (mode 1 or 2, "Operating Sequence"):

- ``cs`` falling starts a cycle: the clock counter is cleared and ``dout`` carries the
  most significant bit of the *previous* conversion's 10-bit result (0 before the first);
- on each of the first four rising clock edges the chip latches ``addr``, most
  significant bit first: the channel of the next conversion;
- on each falling clock edge ``dout`` moves to the next bit (bits 8 .. 0 after edges
  1 .. 9); after the tenth it is driven low, and the addressed channel is converted
  there: its result is what the next cycle shifts out;
- ``cs`` high ends the cycle: the clock and address are ignored, and ``dout`` (high
  impedance on the chip) reads 0.

The lines may be toggled by the CPU (``Pin.value``) or by a PIO state machine (the
Pico-Go's own code: a program that side-sets the clock, ``out``\\ s the address and
``in``\\ s the data, 200 kHz): each clock and address edge is taken at its own instant
(the PIO's, ahead of the firmware's next frame: ``sim_plant.plant.LevelAt``), and the data
bit it sets is on ``dout`` at that instant.

Channel ``i`` (``offsets_m[i]``) reads ``floor_counts`` over white and ``tape_counts``
over the body's ``tape`` or a world's picture's black, in proportion over its greys, at
the instant of its conversion (high over dark: little light comes back). Channel 11 reads
512 ((Vref+ - Vref-) / 2), 12 reads 0 (Vref-), 13 reads 1023 (Vref+); a channel with no
sensor reads 0.

Not modelled: the conversion's time (21 us; a cycle begun sooner reads the result all the
same), the end-of-conversion pin (EOC), the power-down channel (14), the timing limits
(clock up to 2.1 MHz, setup and hold times), noise; what ``dout`` reads while the chip
lets it go (a board's pin with no pull reads what it last read, here 0)."""

import heapq
import math

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.floor import DARK, FloorSensors
from sim_plant.option_table import Num, Row, Rows, length
from sim_plant.plant import NEVER_US, Change

OFFSET = Row((length(-10, 10), length(-10, 10)), "[dx_m, dy_m]")
COUNTS = Num("counts", 0, 1023, whole=True)
REFERENCES = {11: 512, 12: 0, 13: 1023}
"""The self-test channels: (Vref+ - Vref-) / 2, Vref-, Vref+."""


class SerialAdc(FloorSensors):
    """The chip's shift register and its channels' sensors."""

    FIXED_STATE = (*FloorSensors.FIXED_STATE, "label", "signals")

    def __init__(self, name: str, offsets, tape, *, width_m, floor_counts, tape_counts):
        super().__init__(offsets, tape, width_m=width_m, tape_u16=tape_counts, floor_u16=floor_counts, period_us=1)
        self.label = name
        self.signals = {s: f"{name}.{s}" for s in ("cs", "clk", "addr", "dout")}
        self.names = [self.signals["dout"]]
        self.inputs = {self.signals[s]: "level" for s in ("cs", "clk", "addr")}
        self.outputs = {self.signals["dout"]: "level"}
        self.levels_in = {"cs": 1, "clk": 0, "addr": 0}
        self.queue = []  # (instant, order, line, level): the edges to take, each at its instant
        self.order = 0
        self.selected = False
        self.rises = 0  # rising clock edges since cs fell
        self.falls = 0  # falling clock edges since cs fell
        self.address = 0
        self.result = 0  # the last conversion's result: what the next cycle shifts out
        self.word = 0  # the word this cycle shifts out
        self.dout = 0
        self.last = [None] * 14  # each channel's last conversion
        self.conversions = 0
        self.next_us = NEVER_US

    def start(self, t_us: int, plant) -> None:
        self.look_at_world(plant)
        self.next_us = NEVER_US

    def initial_outputs(self) -> dict:
        return {self.signals["dout"]: 0}

    def set_input(self, name: str, value, t_us: int, plant) -> bool:
        line = name[len(self.label) + 1 :]
        at_us = max(t_us, getattr(value, "at_us", t_us))  # (a PIO's edge, seen ahead: at its cycle)
        heapq.heappush(self.queue, (at_us, self.order, line, 1 if value and value > 0 else 0))
        self.order += 1
        self.next_us = math.ceil(self.queue[0][0])
        return False

    def fire(self, t_us: int, plant, out: list) -> None:
        dout = self.dout
        while self.queue and self.queue[0][0] <= t_us:
            at_us, _order, line, level = heapq.heappop(self.queue)
            if level != self.levels_in[line]:
                self.levels_in[line] = level
                self._edge(line, level, plant, t_us)
        self.next_us = math.ceil(self.queue[0][0]) if self.queue else NEVER_US
        if self.dout != dout:
            out.append(Change(t_us, self.signals["dout"], self.dout))

    def _edge(self, line: str, level: int, plant, t_us: int) -> None:
        if line == "cs":
            self.selected = not level
            if self.selected:  # a cycle starts: the last result's MSB out
                self.rises = self.falls = self.address = 0
                self.word = self.result
                self.dout = self.word >> 9 & 1
            else:
                self.dout = 0
            return
        if line != "clk" or not self.selected:
            return  # (the address is sampled at the clock's rising edges)
        if level:
            self.rises += 1
            if self.rises <= 4:
                self.address = self.address << 1 | self.levels_in["addr"]
            return
        self.falls += 1
        if self.falls < 10:
            self.dout = self.word >> (9 - self.falls) & 1
        elif self.falls == 10:
            self.dout = 0
            self.result = self.convert(self.address, plant, t_us)
            self.last[self.address] = self.result
            self.conversions += 1

    def convert(self, channel: int, plant, t_us: int) -> int:
        """Channel ``channel``'s result at ``t_us``."""
        if channel < len(self.offsets):
            self.darks = self.dark(plant.pose_at(t_us))
            return self._levels(self.darks)[channel]
        return REFERENCES.get(channel, 0)

    def truth(self, t_us: int, plant) -> dict:
        darks = self.dark(plant.pose_at(t_us))
        return {
            f"{self.label}_on_tape": [d >= DARK for d in darks],
            f"{self.label}_counts": self._levels(darks),
            f"{self.label}_converted": list(self.last),
            f"{self.label}_conversions": self.conversions,
        }


class Tlc1543(PartType):
    kind = "tlc1543"
    doc = (
        "TLC1543 10-bit serial ADC with floor reflectance sensors on its channels (the Pico-Go's and AlphaBot2's"
        " line sensor board): cs, clk and addr in, dout out; the address latched on the first four rising clock"
        " edges, the previous conversion shifted out MSB first on the falling ones, the addressed channel"
        " converted at the tenth; the lines toggled by the CPU or a PIO state machine, each edge at its instant."
    )
    OPTIONS = (
        Opt(
            "offsets_m",
            Rows(OFFSET, 11, least=1),
            [[0.0, 0.0]],
            "channel i's sensor: its place from the mount, along and across its heading (channels 0, 1, ...)",
        ),
        Opt("floor_counts", COUNTS, 100, "a channel's result over the floor (white: much light back)"),
        Opt("tape_counts", COUNTS, 900, "a channel's result over the tape (black: little light back)"),
    )
    SIGNALS = (
        Sig("cs", "in", "level", "chip select, low for a cycle"),
        Sig("clk", "in", "level", "I/O clock: address in on the rising edges, data out moves on the falling ones"),
        Sig("addr", "in", "level", "address in: the next conversion's channel, MSB first"),
        Sig("dout", "out", "level", "data out: the previous conversion, MSB first; 0 while cs is high"),
    )
    TRUTH = ("{name}_on_tape", "{name}_counts", "{name}_converted", "{name}_conversions")
    VIEWS = (
        View(
            "level",
            "data out against whether each channel's sensor is over the tape",
            signals=("dout",),
            truth=("{name}_on_tape",),
        ),
    )
    MODELLED_FEATURES = (
        "the address latched MSB first on the first four rising clock edges after cs falls",
        "the previous conversion shifted out MSB first: its bit 9 at cs falling, the next at each falling clock"
        " edge, low after the tenth",
        "the addressed channel converted at the tenth falling edge: its sensor's floor (tape, a picture's greys),"
        " or the self-test channels 11, 12, 13 (512, 0, 1023)",
        "edges from the CPU's pins at their instants, and a PIO's at their cycles' instants",
    )
    NOT_MODELLED = (
        "the conversion's 21 us (a cycle begun sooner reads the new result all the same)",
        "EOC, the power-down channel (14), the clock's and the address's timing limits",
        "dout's high impedance while cs is high (it reads 0)",
        "noise, and the spread between sensors",
    )
    needs_body = True
    zero_delay = True  # (an edge the CPU drives: its data bit is on dout at the same instant)
    timed = True  # (a PIO's clock and address edges, each at its cycle's instant: Plant.timed_inputs)

    def check(self) -> None:
        o = self.options
        if o["floor_counts"] > o["tape_counts"]:
            raise ValueError(
                f"floor_counts <= tape_counts expected (high over dark), got {o['floor_counts']}, {o['tape_counts']}"
            )

    def add(self, build: Build) -> None:
        o = self.options
        mx, my, heading = self.mount_rad()
        c, s = math.cos(heading), math.sin(heading)
        offsets = [(mx + dx * c - dy * s, my + dx * s + dy * c) for dx, dy in o["offsets_m"]]
        build.parts.append(
            SerialAdc(
                self.name,
                offsets,
                build.body.get("tape", []),
                width_m=build.body.get("tape_width_m", 0.019),
                floor_counts=o["floor_counts"],
                tape_counts=o["tape_counts"],
            )
        )
