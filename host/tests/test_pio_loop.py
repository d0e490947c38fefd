"""A PIO quadrature decoder in the loop (docs/shim.md, "PIO", cost): a pin only named for
``in_base=Pin(2)`` is no input of the firmware's, so the encoder's 10,000 edges a second
cost the link nothing; the count read equals the plant's edges."""

import pytest

from host.tests import bench_pio

pytestmark = pytest.mark.hil


@pytest.mark.parametrize("in_base", ["Pin(2)", "2"])
def test_a_pio_decoders_pins_cost_the_link_nothing_and_it_counts_every_edge(in_base):
    loop = bench_pio.in_the_loop(0.3, bench_pio.FIRMWARE_PIO, in_base)
    assert loop["edges_per_s"] > 9_000, loop
    assert loop["last_count"] == loop["plant_edges"], loop
    # (one exchange per 20 ms sleep and its read, give or take: not one per 200 edges)
    assert loop["round_trips"] <= 0.3 / 0.020 + 5, loop
