"""A state machine's FIFOs read with MCU time (docs/mcu-time.md; docs/shim.md, "PIO"): a
read is at the firmware's instant, after the compute before it, as a clock read is; the
words and levels an exchange gave answer reads at that exchange's instant only."""

import pytest

from host.tests.conftest import FIRMWARE, bench_app, results

pytestmark = pytest.mark.hil

PLANT = {"body": "bench", "parts": [{"kind": "wire", "name": "w0"}]}
PASS_US = 128  # the program's push: every 32 cycles at 250 kHz


@pytest.mark.parametrize("cpu", ["free", "rp2040@125MHz"])
def test_a_fifo_level_read_after_compute_counts_the_words_pushed_meanwhile(monkeypatch, cpu):
    from host.pytest_plugin import rig_from_keywords

    monkeypatch.setenv("MPYFIL_CPU", cpu)
    app = bench_app("pio_mcu_time", PLANT, board="rpi_pico_bench", wiring={"SRC": "w0.in"}, pins={"SRC": 4})
    rig = rig_from_keywords(app, main_dir=FIRMWARE / "pio_mcu_time", allow_exit=True)
    rig.start()
    try:
        rig.run_for(0.01)
        console = rig.console
    finally:
        rig.stop()
    r = results(console)
    where = f"console: {console!r}"
    assert "words" in r, f"the firmware did not finish; {where}"
    (n0, n1), elapsed = r["levels"], r["elapsed_us"]
    assert r["words"] == [0xFFFFFFFF] * n1, where
    if cpu == "free":
        assert (n1, elapsed) == (0, 0), f"expected no time and no word between the reads, got {n1}, {elapsed} us"
        return
    # the loop between the reads (20 passes) computes on an RP2040: the words pushed meanwhile
    # are there (levels [1, 3], 333 us from the first clock read to the last, by the cost
    # model), no more than the whole span the clock saw holds; a level answered from the
    # first read's reply, at the instant before the compute, would be [1, 1]
    assert n0 < n1 <= elapsed // PASS_US + 1, f"expected the words pushed while it computed; {where}"
