"""A fast output looped back to an input the firmware reads with no IRQ (docs/reliability.md,
"A fast wire into a quiet input"): a PIO PWM and a machine.PWM on wires, the firmware sleeping
40 ms at a time with a UART open; every batch of level changes fits a frame."""

import pytest

from host.tests.conftest import FIRMWARE, bench_app, results

pytestmark = pytest.mark.hil

PLANT = {"body": "bench", "parts": [{"kind": "wire", "name": "w0"}, {"kind": "wire", "name": "w1"}]}
PINS = {"PIO_OUT": 4, "PIO_IN": 5, "PWM_OUT": 6, "PWM_IN": 7}
WIRING = {"PIO_OUT": "w0.in", "PIO_IN": "w0.out", "PWM_OUT": "w1.in", "PWM_IN": "w1.out"}


def test_fast_outputs_into_inputs_with_no_irq_split_into_frames_that_fit():
    from host.pytest_plugin import rig_from_keywords

    app = bench_app("fast_wire", PLANT, board="rpi_pico_bench", wiring=WIRING, pins=PINS)
    rig = rig_from_keywords(app, main_dir=FIRMWARE / "fast_wire")
    rig.start()
    try:
        rig.run_for(0.6)
        console = rig.console
        trips = rig.stats.link_round_trips
    finally:
        rig.stop()
    r = results(console)
    assert r.get("done") == 1, console
    assert r["levels_seen"] >= 2, console  # (the levels read move: the wires carry the PWMs)
    assert trips >= 2 * 0.4 * 9_700 / 200, trips  # (~9,700 + 40,000 changes a second, 200 a STATE at most)
