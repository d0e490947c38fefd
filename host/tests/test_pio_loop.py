"""A PIO quadrature decoder in the loop (docs/shim.md, "PIO", cost): a pin given to
``in_base=Pin(2)`` and not watched is no input of the firmware's until it reads it, so the
encoder's 10,000 edges a second cost the link nothing; the count read equals the plant's edges."""

import pytest

from host.tests import bench_pio

pytestmark = pytest.mark.hil


@pytest.mark.parametrize("in_base", ["Pin(2)", "2"])
def test_a_pio_decoders_pins_cost_the_link_nothing_and_it_counts_every_edge(in_base):
    loop = bench_pio.in_the_loop(0.3, bench_pio.FIRMWARE_PIO, in_base)
    assert loop["edges_per_s"] > 9_000, loop
    assert loop["last_count"] == loop["plant_edges"], loop
    # (the encoder's ~3,000 edges in 0.3 s reach the PIO, not the firmware: a pin named
    # for in_base is no firmware input until it reads it)
    assert loop["changes_sent"] <= 5, loop
    assert loop["round_trips"] <= 0.3 / 0.020 + 5, loop


def test_a_pin_given_to_in_base_is_read_again_when_the_firmware_reads_it():
    reads = "levels = set()\ndef count():\n    levels.add(Pin(2).value())\n    print('levels', sorted(levels))\n"
    firmware = bench_pio.FIRMWARE_PIO.replace("def count():\n", reads, 1)
    loop = bench_pio.in_the_loop(0.3, firmware, "Pin(2)")
    assert "levels [0, 1]" in loop["console"], loop["console"][-300:]  # (10,000 edges a second, read each 20 ms)
    assert loop["changes_sent"] > 1000, loop  # (read: an input again, its edges sent)
    assert loop["last_count"] == loop["plant_edges"], loop
