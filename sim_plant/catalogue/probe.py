"""Part ``probe``: an LED or any board output, recorded as a signal of the plant: its
level (or PWM duty), and how often it changed, in the ground truth."""

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.engine import Part
from sim_plant.option_table import OneOf


class _Probe(Part):
    FIXED_STATE = ("inputs", "outputs")

    def __init__(self, name: str, kind: str):
        self.signal, self.label = f"{name}.in", name
        self.inputs = {self.signal: kind}
        self.value = 0
        self.changes = 0

    def set_input(self, name: str, value, t_us: int, plant) -> bool:
        if value != self.value:
            self.value = value
            self.changes += 1
        return False

    def truth(self, t_us: int, plant) -> dict:
        return {f"{self.label}_value": self.value, f"{self.label}_changes": self.changes}


class Probe(PartType):
    kind = "probe"
    doc = "An LED or any board output, recorded as a plant signal (its value and changes in the truth)."
    OPTIONS = (Opt("signal", OneOf(("level", "duty")), "level", "a pin's level or a PWM's duty_u16"),)
    SIGNALS = (Sig("in", "in", "level or duty", "what the board drives"),)
    TRUTH = ("{name}_value", "{name}_changes")
    VIEWS = (View("level", "the output over time", signals=("in",), truth=("{name}_value",)),)

    def signals(self) -> dict[str, tuple[str, str]]:
        return {f"{self.name}.in": ("in", self.options["signal"])}

    def add(self, build: Build) -> None:
        build.parts.append(_Probe(self.name, self.options["signal"]))
