"""Part ``relay``: a relay module on a board output (``<name>.in``): its coil pulls in when
the input is at its active level (high for an NPN driver, low for a PNP one,
``active_low``); the truth says whether the normally-open contact is closed and how
many times it switched."""

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.engine import Part
from sim_plant.option_table import Flag


class _Relay(Part):
    FIXED_STATE = ("inputs", "outputs")

    def __init__(self, name: str, active_low: bool):
        self.label, self.active_low = name, active_low
        self.inputs = {f"{name}.in": "level"}
        self.closed = False
        self.switches = 0

    def set_input(self, name: str, value, t_us: int, plant) -> bool:
        closed = (not value) if self.active_low else bool(value)
        if closed != self.closed:
            self.closed = closed
            self.switches += 1
        return False

    def truth(self, t_us: int, plant) -> dict:
        return {f"{self.label}_closed": int(self.closed), f"{self.label}_switches": self.switches}


class Relay(PartType):
    kind = "relay"
    doc = "A relay module on a board output: the contact closes at the input's active level."
    OPTIONS = (Opt("active_low", Flag(), False, "true: a low input pulls it in (a PNP driver)"),)
    SIGNALS = (Sig("in", "in", "level", "the module's IN pin"),)
    TRUTH = ("{name}_closed", "{name}_switches")
    VIEWS = (View("level", "the coil's input over time", signals=("in",), truth=("{name}_closed",)),)

    def add(self, build: Build) -> None:
        build.parts.append(_Relay(self.name, self.options["active_low"]))
