"""Part ``tether``: the cable a robot trails, catching on a wall at a spin on the spot
with chance ``snag_p`` and pulling the robot off its pose (seed 002 §5.7,
:mod:`sim_plant.physics.tether`: 18 of 20 runs succeeded, both failures from the tether)."""

from sim_plant.catalogue.base import Build, Opt, PartType, View
from sim_plant.option_table import FRACTION, Num, Rows
from sim_plant.physics.tether import P_SNAG, TetherSnag


class Tether(PartType):
    kind = "tether"
    doc = "A trailing tether that may snag at a spin on the spot and pull the robot off its pose."
    OPTIONS = (
        Opt("snag_p", FRACTION, P_SNAG, "chance a spin snags (0: it never does)"),
        Opt("pull_m", Num("metres", 0, 10), 0.08, "how far a snag pulls the robot back"),
        Opt("twist_deg", Num("degrees", 0, 360), 25.0, "how far it twists the robot"),
        Opt("delay_ms", Num("milliseconds", 0, 100_000), 150, "from the spin's start to the pull"),
        Opt("spins", Rows(Num("", 0, 10_000, whole=True), 64), None, "only these spins (0 first) may snag; unset: any"),
    )
    TRUTH = ("snags",)
    VIEWS = (View("count", "the snags against the spins", truth=("snags",)),)
    needs_body = True

    def add(self, build: Build) -> None:
        o = self.options
        if o["snag_p"] <= 0:
            return  # (a tether that never snags changes nothing)
        build.parts.append(
            TetherSnag(
                p_snag=o["snag_p"],
                pull_m=o["pull_m"],
                twist_deg=o["twist_deg"],
                delay_ms=o["delay_ms"],
                spins=o["spins"],
            )
        )
