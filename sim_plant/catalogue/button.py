"""Part ``button``: a push-button pressed at scheduled times, active low (to ground, on a
pull-up) or active high (to 3V3, on a pull-down), with contact chatter when asked
(:class:`sim_plant.physics.button.Buttons`)."""

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.controls import Control
from sim_plant.option_table import TIME, Flag, Num, OneOf, Row, Rows
from sim_plant.physics.button import Buttons


class _Button(Buttons):
    """One button, its signal ``<name>.out``; active high flips its levels."""

    def __init__(self, name: str, presses, bounce_us: int, active_low: bool):
        super().__init__([name], [(name, t0, t1) for t0, t1 in presses], bounce_us)
        signal = f"{name}.out"
        self.outputs = {signal: "level"}
        self.events = [(t, signal, level if active_low else 1 - level) for t, _, level in self.events]
        self.released = 1 if active_low else 0

    def initial_outputs(self) -> dict:
        return dict.fromkeys(self.outputs, self.released)


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
    )
    SIGNALS = (Sig("out", "out", "level", "the button's level"),)
    TRUTH = ()
    VIEWS = (View("level", "the button's level over time", signals=("out",)),)
    CONTROLS = (Control("pressed", OneOf((0, 1)), "1: held down, 0: let go (at the scenario's instant)"),)

    def check(self) -> None:
        _Button(self.name, self.options["presses"], 0, True)  # refuse a release before its press

    def control_change(self, control: str, value) -> tuple | None:
        super().control_change(control, value)
        pressed_level = 0 if self.options["active_low"] else 1
        return f"{self.name}.out", pressed_level if value else 1 - pressed_level

    def add(self, build: Build) -> None:
        o = self.options
        build.parts.append(_Button(self.name, o["presses"], o["bounce_us"], o["active_low"]))
