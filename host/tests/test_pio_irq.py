"""PIO IRQ handlers (docs/shim.md, "PIO", IRQs): StateMachine.irq on a pulse counter's
``irq(rel(0))`` and PIO(0).irq on a program that raises ``irq(block, 1)`` and waits for the
CPU to clear its flag; each raise runs its handler once, soon after (a poll each POLL_US)."""

import pytest

from host.tests.conftest import FIRMWARE, bench_app, results

pytestmark = pytest.mark.hil

PLANT = {"body": "bench", "parts": [{"kind": "wire", "name": "w0"}]}
PINS = {"SRC": 4, "ECHO": 5}
WIRING = {"SRC": "w0.in", "ECHO": "w0.out"}


@pytest.fixture(scope="module")
def r():
    from host.pytest_plugin import rig_from_keywords

    app = bench_app("pio_irq", PLANT, board="rpi_pico_bench", wiring=WIRING, pins=PINS)
    rig = rig_from_keywords(app, main_dir=FIRMWARE / "pio_irq")
    rig.start()
    try:
        rig.run_for(0.3)
        console = rig.console
    finally:
        rig.stop()
    out = results(console)
    assert out.get("done") == 1, console
    return out


def test_a_state_machines_irq_handler_runs_once_for_each_pulse(r):
    assert r["pulses"] in (49, 50, 51), r  # 500 Hz for 100 ms
    assert all(1000 <= g <= 3000 for g in r["gaps_us"]), r  # (each within a poll of its edge)


def test_a_pio_irq_handler_clears_the_flag_the_program_waits_on(r):
    # 32 * 32 + 4 cycles at 100 kHz: ~10.3 ms a tick, each waiting for the CPU to clear flag 1
    assert 8 <= r["ticks"] <= 10, r
    assert r["tick_flags"] == [0x200] and r["tick_words"] == [0xFFFFFFFF], r
    assert r["irq_flags"] == [1, 0x200], r
