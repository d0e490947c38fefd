"""Part ``button``: a push-button pressed at scheduled times, active low (to ground, on a
pull-up) or active high (to 3V3, on a pull-down), with contact chatter when asked
(:class:`sim_plant.physics.button.Buttons`)."""

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.controls import Control
from sim_plant.option_table import TIME, Flag, Name, Num, OneOf, Row, Rows
from sim_plant.physics.button import Buttons
from sim_plant.plant import Change


class _Button(Buttons):
    """One button, its signal ``<name>.out``; active high flips its levels. With an LED on
    its line (``led``: the level that lights it), or a chip's input (``shares``), the line
    is an input of the part too: the board's level while a pin drives it, the button's while
    the pin lets it go; the pin's level goes on to the chip's input while it drives it."""

    FIXED_STATE = (*Buttons.FIXED_STATE, "shares", "io", "targets")
    targets_option = "shares"  # (the option that names its targets, in the plant's check of them)

    def __init__(
        self, name: str, presses, bounce_us: int, active_low: bool, led: str = "none", shares: str | None = None
    ):
        super().__init__([name], [(name, t0, t1) for t0, t1 in presses], bounce_us)
        signal = f"{name}.out"
        self.signal = signal
        self.outputs = {signal: "level"}
        self.events = [(t, signal, level if active_low else 1 - level) for t, _, level in self.events]
        self.released = 1 if active_low else 0
        self.label = name
        self.lit_by = None if led == "none" else (0 if led == "low" else 1)
        self.shares = shares
        self.targets = () if shares is None else (shares,)  # (checked by the plant: another part's input)
        self.io = self.lit_by is not None or shares is not None
        if self.io:
            self.inputs = {signal: "level"}
        self.level = self.released  # the button's own (what a pin reads once it lets the line go)
        self.line = self.released
        self.driven = None  # the board's level on the line, None while it lets it go

    def initial_outputs(self) -> dict:
        return dict.fromkeys(self.outputs, self.released)

    def fire(self, t_us: int, plant, out: list) -> None:
        if not self.io:
            super().fire(t_us, plant, out)
            return
        pressed: list = []
        super().fire(t_us, plant, pressed)
        for change in pressed:
            self.level = change[2]
        line = self.level if self.driven is None else self.driven
        if line != self.line:
            self.line = line
            out.append(Change(t_us, self.signal, line))

    def set_input(self, name: str, value, t_us: int, plant) -> bool:
        if not self.io:
            return super().set_input(name, value, t_us, plant)
        self.driven = None if value is None or value < 0 else (1 if value else 0)
        self.next_us = t_us  # (the line's level at this instant: fire)
        if self.shares is not None and self.driven is not None:  # (the chip's input, at the same instant)
            plant.set_input(self.shares, self.driven)
        return False

    def truth(self, t_us: int, plant) -> dict:
        lit = None if self.lit_by is None else int(self.driven == self.lit_by)
        return {f"{self.label}_led": lit}


class Button(PartType):
    kind = "button"
    doc = "A push-button, active low or high, pressed at scheduled times (presses)."
    OPTIONS = (
        Opt(
            "active_low",
            Flag(),
            True,
            "true: to ground on a pull-up (reads 0 pressed); false: to 3V3 on a pull-down (reads 1 pressed)",
        ),
        Opt(
            "presses", Rows(Row((TIME, TIME), "[t_press_s, t_release_s]"), 1000), [], "when it is pressed and released"
        ),
        Opt("bounce_us", Num("microseconds", 0, 1_000_000, whole=True), 0, "contact chatter at each press and release"),
        Opt(
            "led",
            OneOf(("none", "low", "high")),
            "none",
            "an LED on the button's line, lit while a pin drives it low (low: from 3V3, the 3pi+ 2040's yellow "
            "LED and button A on GP25) or high: the line is the pin's while it drives it, the button's while the "
            "pin lets it go (an input, or its output disabled by an IO_BANK0 override)",
        ),
        Opt(
            "shares",
            Name(),
            None,
            "a chip's input on the button's line (the 3pi+ 2040's button C on the display's DC, GP0: "
            "display.dc): the line is the pin's while it drives it, and that level goes on to the chip's input; "
            "the button's while the pin lets it go",
        ),
    )
    SIGNALS = (
        Sig("out", "out", "level", "the button's level", (("led", ("none",)),)),
        Sig(
            "out",
            "io",
            "level",
            "the line: the pin's level while it drives it, else the button's (also with shares set)",
            (("led", ("low", "high")),),
        ),
    )
    TRUTH = ("{name}_led",)
    VIEWS = (View("level", "the button's level over time", signals=("out",)),)
    CONTROLS = (Control("pressed", OneOf((0, 1)), "1: held down, 0: let go (at the scenario's instant)"),)

    @property
    def io(self) -> bool:
        """The line is the pin's too (an LED on it, or a chip's input)."""
        return self.options["led"] != "none" or self.options["shares"] is not None

    @property
    def zero_delay(self) -> bool:  # (an io line: the pin's drive is on the line at the same instant)
        return self.io

    def signals(self) -> dict[str, tuple[str, str]]:
        signals = super().signals()
        if self.options["shares"] is not None:  # (SIGNALS' io line is declared for an LED; a chip's input too)
            signals[f"{self.name}.out"] = ("io", "level")
        return signals

    def check(self) -> None:
        _Button(self.name, self.options["presses"], 0, True)  # refuse a release before its press

    def control_change(self, control: str, value) -> tuple | None:
        super().control_change(control, value)
        pressed_level = 0 if self.options["active_low"] else 1
        return f"{self.name}.out", pressed_level if value else 1 - pressed_level

    def add(self, build: Build) -> None:
        o = self.options
        build.parts.append(_Button(self.name, o["presses"], o["bounce_us"], o["active_low"], o["led"], o["shares"]))
