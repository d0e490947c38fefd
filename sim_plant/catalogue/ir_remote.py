"""Part ``ir_remote``: an infrared remote control's key presses as an IR receiver module
(VS1838B, TSOP38238 class: 38 kHz, demodulated) gives them to a pin, in the NEC protocol:
the kits' credit-card remotes (the Waveshare Pico-Go's and AlphaBot2's, Elegoo's, ...).

The receiver's output is low while the 38 kHz carrier is on (a burst) and high between.
A key pressed at ``t_s`` sends one NEC frame from there: a 9 ms burst, a 4.5 ms space,
32 bits least significant first (the address, its inverse, the command, its inverse),
each a 562.5 us burst then a space of 562.5 us (a 0) or 1687.5 us (a 1), and a last
562.5 us burst. Held for ``held_s``, it sends a repeat code (a 9 ms burst, a 2.25 ms
space, a 562.5 us burst) every 108 ms from the frame's start while it is held. Each edge
is at the nearest microsecond of its instant. Press rows that overlap send one after the
other's last burst, with a 4.5 ms space between (a remote sends nothing new while a key is
held; the space is ours, so that bursts do not touch).

Not modelled: the carrier itself (the receiver's demodulated output is the signal), the
receiver's delay and its pulse-width distortion (a VS1838B's bursts may come out up to
~100 us longer), the line of sight, other IR light; the extended NEC addresses (16 bits,
no inverse: set ``address`` and its inverse is sent)."""

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.engine import Part
from sim_plant.option_table import TIME, Num, Row, Rows
from sim_plant.plant import NEVER_US, Change

BYTE = Num("", 0, 255, whole=True)
BURST_US, SPACE_US, BIT_US = 9000.0, 4500.0, 562.5
REPEAT_SPACE_US, REPEAT_EVERY_US = 2250.0, 108_000.0


def nec_frame(address: int, command: int) -> list:
    """One frame's (offset_us, level) edges from its start: 0 a burst, 1 a space."""
    edges, t = [(0.0, 0)], BURST_US
    edges.append((t, 1))
    t += SPACE_US
    word = address | (address ^ 0xFF) << 8 | command << 16 | (command ^ 0xFF) << 24
    for i in range(32):
        edges.append((t, 0))
        t += BIT_US
        edges.append((t, 1))
        t += 3 * BIT_US if word >> i & 1 else BIT_US
    edges += [(t, 0), (t + BIT_US, 1)]
    return edges


def nec_repeat() -> list:
    t = BURST_US + REPEAT_SPACE_US
    return [(0.0, 0), (BURST_US, 1), (t, 0), (t + BIT_US, 1)]


class _Remote(Part):
    """The receiver's output, its edges planned from the press rows."""

    FIXED_STATE = ("inputs", "outputs", "label", "signal")

    def __init__(self, name: str, address: int, presses):
        self.label = name
        self.signal = f"{name}.out"
        self.outputs = {self.signal: "level"}
        self.events = []  # (t_us, level), in time order
        self.sent = []  # (t_us, command): each frame's start
        free_us = 0.0
        for t_s, command, held_s in sorted(presses):
            start = max(t_s * 1e6, free_us)
            frames = [(start, nec_frame(address, int(command)), int(command))]
            t = start + REPEAT_EVERY_US
            while t < (t_s + held_s) * 1e6:
                frames.append((t, nec_repeat(), None))
                t += REPEAT_EVERY_US
            for at, edges, code in frames:
                self.events += [(round(at + dt), level) for dt, level in edges]
                if code is not None:
                    self.sent.append((round(at), code))
            free_us = self.events[-1][0] + SPACE_US  # (a space after the last burst before the next frame)
        self.index = 0
        self.level = 1
        self.next_us = self.events[0][0] if self.events else NEVER_US

    def initial_outputs(self) -> dict:
        return {self.signal: 1}

    def fire(self, t_us: int, plant, out: list) -> None:
        while self.index < len(self.events) and self.events[self.index][0] <= t_us:
            level = self.events[self.index][1]
            self.index += 1
            if level != self.level:
                self.level = level
                out.append(Change(t_us, self.signal, level))
        self.next_us = self.events[self.index][0] if self.index < len(self.events) else NEVER_US

    def truth(self, t_us: int, plant) -> dict:
        sent = [code for at, code in self.sent if at <= t_us]
        return {f"{self.label}_sent": sent}


class IrRemote(PartType):
    kind = "ir_remote"
    doc = (
        "An IR remote's key presses through a 38 kHz receiver module (low while the carrier is on), in the NEC"
        " protocol: a 9 ms burst, a 4.5 ms space, address, its inverse, command, its inverse (LSB first, 562.5 us"
        " bursts, spaces of 562.5 us for a 0 and 1687.5 us for a 1), and repeat codes every 108 ms while held."
    )
    OPTIONS = (
        Opt("address", BYTE, 0, "the remote's address (the kits' credit-card remotes: 0x00)"),
        Opt(
            "presses",
            Rows(Row((TIME, BYTE, TIME), "[t_press_s, command, held_s]"), 1000),
            [],
            "when each key is pressed, its command byte, and how long it is held (0: a tap, one frame)",
        ),
    )
    SIGNALS = (Sig("out", "out", "level", "the receiver's output: low during a burst, high between"),)
    TRUTH = ("{name}_sent",)
    VIEWS = (View("level", "the receiver's output over time", signals=("out",)),)

    def add(self, build: Build) -> None:
        o = self.options
        build.parts.append(_Remote(self.name, o["address"], o["presses"]))
