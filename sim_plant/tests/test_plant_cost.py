"""The benchmark's scenarios measure robots under way, not pushing against a wall."""

import pytest

from sim_plant import plant_cost


@pytest.mark.parametrize("name, make, drive", plant_cost.ROBOTS, ids=[r[0].split()[0] for r in plant_cost.ROBOTS])
def test_bench_scenarios_cruise_without_touching_anything(name, make, drive):
    plant = make()
    plant.reset(1)
    for k in range(plant_cost.QUANTA):
        drive(plant, k)
        plant.advance_to((k + 1) * plant_cost.QUANTUM_US)
    truth = plant.truth()
    assert truth["contacts"] == [] and truth["distance_m"] > 3.0, name
    us, changes = plant_cost.run(make, drive, host_loop=True, quanta=20)
    assert us > 0 and changes > 0
