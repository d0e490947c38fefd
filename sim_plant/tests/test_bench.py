"""The benchmark's scenarios measure robots under way, not pushing against a wall."""

import pytest

from sim_plant import bench


@pytest.mark.parametrize("name, make, drive", bench.ROBOTS, ids=[r[0].split()[0] for r in bench.ROBOTS])
def test_bench_scenarios_cruise_without_touching_anything(name, make, drive):
    plant = make()
    plant.reset(1)
    for k in range(bench.QUANTA):
        drive(plant, k)
        plant.advance_to((k + 1) * bench.QUANTUM_US)
    truth = plant.truth()
    assert truth["contacts"] == [] and truth["distance_m"] > 3.0, name
    us, changes = bench.run(make, drive, host_loop=True, quanta=20)
    assert us > 0 and changes > 0
