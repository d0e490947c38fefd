"""A firmware that fills its heap, catches MemoryError and goes on runs on as on a board:
the shim's own sleeps, reads, prints and callbacks find memory when the firmware has
left none (docs/shim.md, "A full heap")."""

import dataclasses

import pytest

from host.rig.config.app import InterpreterSettings
from host.tests.conftest import FIRMWARE, results, shim_app

pytestmark = pytest.mark.hil

SCRIPT = [(t, "a", k % 2) for k, t in enumerate(range(5_000, 520_000, 20_000), start=1)]
SCRIPT += [(0, "adc", 1000), (250_000, "adc", 3000)]
HEAP = "64K"  # the firmware's heap: small, so that filling it is quick


@pytest.fixture
def run_full(make_rig):
    def run(case, duration_s):
        app = dataclasses.replace(shim_app(SCRIPT), interpreter=InterpreterSettings(heap_size=HEAP))
        rig = make_rig(app, main_dir=FIRMWARE / case, allow_exit=True)
        rig.run_for(duration_s)
        rig.stop()
        return rig, results(rig.console)

    return run


def test_a_firmware_that_frees_half_after_a_memory_error_sleeps_reads_and_keeps_its_timer(run_full):
    rig, r = run_full("heap_full_recovers", 0.5)
    assert "Traceback" not in rig.console, rig.console
    assert 10 < r["taken"] < 2048 and r["kept"] == r["taken"] // 2, r
    assert r["elapsed"] == 100 and r["ticks"] == 5, r
    assert "out of memory: backing off" in rig.console, rig.console
    levels = r["levels"]  # sampled every 10 ms, the input toggling every 20 ms
    assert sum(levels) == 5 and all(levels[i] != levels[i + 2] for i in range(8)), r
    assert r["reads"] == [1000] * 10, r


def test_a_firmware_that_keeps_its_heap_full_sleeps_reads_prints_and_runs_its_callbacks(run_full):
    rig, r = run_full("heap_kept_full", 1.0)
    assert "Traceback" not in rig.console, rig.console
    assert r["left"] < 256, f"expected the firmware to have filled its heap to its last blocks: {r}"
    assert r["elapsed"] == 500 and r["ticks"] == 50, r
    assert rig.console.count("tick\n") == 50, rig.console
    assert r["edges"] == 13 and r["highs"] == 26, r
    assert r["total"] == 1000 * 24 + 3000 * 26, r


def test_each_package_finds_its_own_module_in_a_relative_import_whatever_else_is_loaded(run_case):
    """The shim takes machine (and its buses) before the firmware runs, so more modules are
    loaded: a relative import still goes to the importing package's own module, not to the
    first package sys.modules happens to list (asyncio, another of the firmware's)."""
    rig, r = run_case("relative_packages", 0.1)
    assert r == {"a": "aa", "b": "bb"}, rig.console
