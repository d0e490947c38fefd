"""Part ``rotary_knob``: a KY-040 style rotary encoder with a push switch, turned and
pressed at scheduled times: its ``clk`` and ``dt`` outputs in quadrature (the module's
pull-ups hold both high at a detent) and its ``sw`` switch to ground (a board pull-up).

A detent clockwise is a full cycle of the two, CLK first: CLK falls, DT falls, CLK
rises, DT rises, ``edge_us`` apart; counter-clockwise DT leads. So a firmware that reads
DT when CLK falls sees 1 turning clockwise and 0 counter-clockwise, as on Wokwi's KY-040.
Turns (``turns``: ``[t_s, detents]``, negative counter-clockwise) and presses
(``presses``) are scheduled; a scenario's set-control ``pressed`` holds the switch down or
lets it go. The truth has the knob's position in detents (clockwise positive)."""

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.controls import Control
from sim_plant.engine import Part
from sim_plant.option_table import TIME, Num, OneOf, Row, Rows
from sim_plant.plant import NEVER_US, Change

CLOCKWISE = (("clk", 0), ("dt", 0), ("clk", 1), ("dt", 1))
COUNTER = (("dt", 0), ("clk", 0), ("dt", 1), ("clk", 1))


def schedule(name: str, turns, presses, edge_us: int) -> list:
    """(t_us, signal, level, detents) in time order: the knob's edges and the switch's."""
    events = []
    for t_s, detents in turns:
        t_us = round(t_s * 1e6)
        for _ in range(abs(int(detents))):
            for i, (pin, level) in enumerate(CLOCKWISE if detents > 0 else COUNTER):
                last = i == len(CLOCKWISE) - 1
                events.append((t_us, f"{name}.{pin}", level, (1 if detents > 0 else -1) if last else 0))
                t_us += edge_us
    for t_press_s, t_release_s in presses:
        if not t_press_s < t_release_s:
            raise ValueError(f"presses: pressed at {t_press_s} s, released at {t_release_s} s")
        events += [(round(t_press_s * 1e6), f"{name}.sw", 0, 0), (round(t_release_s * 1e6), f"{name}.sw", 1, 0)]
    return sorted(events, key=lambda e: e[0])


class _Knob(Part):
    FIXED_STATE = ("events", "inputs", "outputs")

    def __init__(self, name: str, events: list):
        self.label, self.events = name, events
        self.outputs = {f"{name}.{pin}": "level" for pin in ("clk", "dt", "sw")}
        self.i, self.position = 0, 0
        self.next_us = events[0][0] if events else NEVER_US

    def initial_outputs(self) -> dict:
        return dict.fromkeys(self.outputs, 1)

    def fire(self, t_us: int, plant, out: list) -> None:
        while self.i < len(self.events) and self.events[self.i][0] <= t_us:
            _t, signal, level, detent = self.events[self.i]
            out.append(Change(t_us, signal, level))
            self.position += detent
            self.i += 1
        self.next_us = self.events[self.i][0] if self.i < len(self.events) else NEVER_US

    def truth(self, t_us: int, plant) -> dict:
        return {f"{self.label}_position": self.position}


class RotaryKnob(PartType):
    kind = "rotary_knob"
    doc = "A KY-040 rotary encoder with a push switch: CLK/DT in quadrature a detent, SW to ground."
    OPTIONS = (
        Opt(
            "turns",
            Rows(Row((TIME, Num("detents", -1000, 1000, whole=True)), "[t_s, detents]"), 1000),
            [],
            "when it is turned and by how many detents (negative: counter-clockwise)",
        ),
        Opt("presses", Rows(Row((TIME, TIME), "[t_press_s, t_release_s]"), 1000), [], "when its switch is pressed"),
        Opt(
            "edge_us", Num("microseconds", 10, 100_000, whole=True), 1000, "between the edges of a detent (4 a detent)"
        ),
    )
    SIGNALS = (
        Sig("clk", "out", "level", "CLK (A): high at a detent; falls first turning clockwise"),
        Sig("dt", "out", "level", "DT (B): high at a detent; falls first turning counter-clockwise"),
        Sig("sw", "out", "level", "the push switch: 0 pressed (to ground)"),
    )
    TRUTH = ("{name}_position",)
    VIEWS = (View("level", "CLK, DT and SW over time", signals=("clk", "dt", "sw"), truth=("{name}_position",)),)
    CONTROLS = (Control("pressed", OneOf((0, 1)), "1: the switch held down, 0: let go"),)

    def check(self) -> None:
        o = self.options
        schedule(self.name, o["turns"], o["presses"], o["edge_us"])

    def control_change(self, control: str, value) -> tuple | None:
        super().control_change(control, value)
        return f"{self.name}.sw", 0 if value else 1

    def add(self, build: Build) -> None:
        o = self.options
        build.parts.append(_Knob(self.name, schedule(self.name, o["turns"], o["presses"], o["edge_us"])))
