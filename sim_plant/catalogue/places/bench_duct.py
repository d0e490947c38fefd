"""World ``bench_duct``: the long straight duct of the speed-loop step tests (:func:`sim_plant.duct.bench_duct`)."""

from sim_plant.catalogue.base import WorldType
from sim_plant.duct import DUCT_START, bench_duct


class BenchDuct(WorldType):
    kind = "bench_duct"
    doc = "An 8 m straight duct for the speed-loop step tests (seed 002 App. D.5)."

    def build(self):
        return bench_duct(), DUCT_START
