"""Part ``coverage``: the floor a cleaning footprint has swept, as ground truth only (no
board signal): the fraction of the world's free cells its path has covered
(:mod:`sim_plant.physics.coverage`), for robots judged on how much floor they cover."""

from sim_plant.catalogue.base import Build, Opt, PartType, View
from sim_plant.option_table import Num, length
from sim_plant.physics.coverage import CoverageGrid, CoverageRecorder


class _Recorder(CoverageRecorder):
    """The recorder, its grid laid over the world the body is in when the plant starts
    (the world is built after the parts)."""

    def __init__(self, cell_m: float, half_width_m: float):
        super().__init__(None)
        self.cell_m, self.half_width_m = cell_m, half_width_m

    def start(self, t_us: int, plant) -> None:
        self.grid = CoverageGrid(plant.world, self.cell_m, self.half_width_m)
        super().start(t_us, plant)


class Coverage(PartType):
    kind = "coverage"
    doc = "The floor the robot's footprint has swept (ground truth only: the fraction of free floor covered)."
    OPTIONS = (
        Opt("coverage_cell_m", length(0.005, 10), 0.1, "the grid's cell"),
        Opt(
            "half_width_m",
            Num("metres", 0, 10, above=True, none=True),
            None,
            "half the swept footprint's width; unset: the body's radius",
        ),
    )
    TRUTH = ("coverage_fraction",)
    VIEWS = (View("coverage", "the fraction of the free floor swept so far", truth=("coverage_fraction",)),)
    needs_body = True

    def add(self, build: Build) -> None:
        o = self.options
        half_width_m = o["half_width_m"] or build.body.get("body_radius_m", 0.1)
        build.parts.append(_Recorder(o["coverage_cell_m"], half_width_m))
