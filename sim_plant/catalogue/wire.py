"""Part ``wire``: a wire on a bench from a board output to a board input, as upstream's
hardware tests wire a board (:mod:`sim_plant.physics.wire` is its engine). A level written to
``<name>.in`` is on ``<name>.out`` at the same instant (the plant is then zero-delay: the
shim syncs a read that follows a write); a PWM on the input drives the output with its
waveform, edges rounded to the microsecond."""

from sim_plant.catalogue.base import Build, PartType, Sig, View
from sim_plant.physics.wire import WirePart


class Wire(PartType):
    kind = "wire"
    doc = "A wire from a board output to a board input: a level at once, a PWM as its waveform."
    OPTIONS = ()
    SIGNALS = (
        Sig("in", "in", "pwm", "what the board drives: a level, or a PWM's waveform"),
        Sig("out", "out", "level", "what the board reads: the input's level at the same instant"),
    )
    TRUTH = ("{name}_level", "{name}_edges")
    VIEWS = (View("level", "the wire's level over time", signals=("out",), truth=("{name}_level",)),)
    zero_delay = True

    def add(self, build: Build) -> None:
        WirePart.on(build.parts).add(wires=(self.name,))
