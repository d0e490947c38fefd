"""The bus tests that poll for long, and the bench's bus-heavy robot, read the same bytes
with the host's bus images as with an exchange a transfer (host/tests/test_bus_image.py
says how they are compared; these take a minute or more, so they run in make hil, which
runs with a report, and are skipped in make test)."""

import pytest

from host.tests.test_bus_image import SLOW_BUS_TESTS, bench_robot_both_ways, case_id, cases, compare, kit_demo_both_ways

pytestmark = [
    pytest.mark.hil,
    pytest.mark.long,
    pytest.mark.skipif("not config.getoption('--hil-report')", reason="make hil runs the slow bus comparisons"),
]
SLOW = cases(SLOW_BUS_TESTS)


@pytest.mark.parametrize(("module", "name", "polls", "params"), SLOW, ids=[case_id(c) for c in SLOW])
def test_a_slow_bus_test_reads_the_same_bytes_with_images(tmp_path, monkeypatch, module, name, polls, params):
    compare(tmp_path, monkeypatch, module, name, polls, params)


def test_the_bus_heavy_bench_robot_reads_the_same_bytes_with_images(tmp_path, monkeypatch):
    bench_robot_both_ways(tmp_path, monkeypatch)


@pytest.mark.parametrize("kit", ["pololu_3pi_2040", "xrp"])
def test_a_kit_demo_reads_the_same_bytes_with_images(tmp_path, monkeypatch, kit):
    kit_demo_both_ways(tmp_path, monkeypatch, kit)
