"""The apps' budgets take their expected values from the plant they measure."""

import pytest

from host.rig.config.apps import get_app
from sim_plant.catalogue.assembly import rig_plant_table


@pytest.mark.parametrize(
    "app, option",
    [("rover", "sonar.period_us"), ("pool_cleaner", "sonar.period_us"), ("pool_cleaner_adc", "sonar_l.period_us")],
)
def test_sonar_period_budget_reads_the_plants_sonar_period(app, option):
    spec = get_app(app)
    for period_us in (500_000, 250_000, 1_000_000):
        plant = spec.make_plant(**{option: period_us})
        budgets = {b.name: b for b in spec.make_budgets(plant)}
        source = budgets["sonar.period"].source
        assert budgets["sonar.period"].period_us == period_us == plant.sample_period_us(source)
        assert f"{period_us // 1000} ms" in budgets["sonar.period"].description


def test_the_rovers_sonar_period_budget_reads_its_sonar_parts_period():
    spec = get_app("rover")
    for period_us in (500_000, 250_000, 1_000_000):
        parts = rig_plant_table(spec.rig_file, parts={"sonar": {"period_us": period_us}})["parts"]
        plant = spec.make_plant(parts=parts)
        budgets = {b.name: b for b in spec.make_budgets(plant)}
        assert budgets["sonar.period"].period_us == period_us == plant.sample_period_us("sonar.adc")
        assert f"{period_us // 1000} ms" in budgets["sonar.period"].description


def test_the_adc_pool_cleaner_checks_its_left_sonar_and_the_nmea_one_its_uart():
    pool, adc = get_app("pool_cleaner"), get_app("pool_cleaner_adc")
    assert {b.name: b.source for b in pool.make_budgets(pool.make_plant())}["sonar.period"] == "sonar.uart"
    assert {b.name: b.source for b in adc.make_budgets(adc.make_plant())}["sonar.period"] == "sonar_l.adc"
