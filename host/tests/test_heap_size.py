"""``[interpreter] heap_size`` is the firmware's heap, as on its board: the shim's share
(host/rig/targets/heap.py) is on top and held by the shim once it has started, so the firmware
finds heap_size free; the least a rig file takes runs a firmware with machine, time and
asyncio, and one step below is refused by ``check``."""

import dataclasses
import shutil

import pytest

from host.core.paths import REPO
from host.rig.config.app import InterpreterSettings
from host.rig.targets.heap import HEAP_MIN_BYTES
from host.tests.conftest import FIRMWARE, results, shim_app
from host.tests.test_rigfile_bounds import GOOD, check

STEP = 1024  # heap sizes are written in K


@pytest.fixture
def pico(tmp_path):
    folder = tmp_path / "pico_bot"
    folder.mkdir()
    shutil.copy(REPO / "examples" / "pico_bot" / "main.py", folder)
    return folder


def run(make_rig, case, heap_size, duration_s):
    app = dataclasses.replace(shim_app(console_baud=0), interpreter=InterpreterSettings(heap_size=heap_size))
    rig = make_rig(app, main_dir=FIRMWARE / case, allow_exit=True)
    rig.run_for(duration_s)
    rig.stop()
    return rig, results(rig.console)


@pytest.mark.hil
def test_the_least_heap_a_rig_file_takes_runs_a_firmware_with_machine_time_and_asyncio(make_rig):
    rig, r = run(make_rig, "heap_smallest", f"{HEAP_MIN_BYTES // STEP}K", 0.5)
    assert "Traceback" not in rig.console, rig.console
    assert r["readings"] == 20 and r["ticks"] >= 19, r
    assert rig.console.count("step ") == 20, rig.console
    assert 0 < r["free"] < HEAP_MIN_BYTES, f"expected the firmware's own heap only, {HEAP_MIN_BYTES} bytes: {r}"


@pytest.mark.hil
@pytest.mark.parametrize("heap_kib", [HEAP_MIN_BYTES // STEP, 64, 1024])
def test_the_firmware_finds_its_heap_size_free_as_it_starts(make_rig, heap_kib):
    """gc.mem_free() at main.py's start is the board's heap less what main.py took to
    compile and run its first lines (a few K), not the interpreter's whole heap."""
    rig, r = run(make_rig, "heap_free", f"{heap_kib}K", 0.1)
    assert heap_kib * 1024 - 8 * 1024 < r["free"] <= heap_kib * 1024, r


@pytest.mark.hil
@pytest.mark.parametrize("heap_kib", [HEAP_MIN_BYTES // STEP, 64, 1024])
def test_the_firmware_can_take_nearly_all_its_free_heap_in_one_piece_as_it_starts(make_rig, heap_kib):
    """A board's heap is one piece at power-on: the shim's objects, kept wherever its
    start-up left them, are not among the firmware's (the firmware's heap is set apart
    before that start-up); what is not one piece is main.py's own compile (its parser's
    garbage below its names' qstrs), as on a board."""
    rig, r = run(make_rig, "heap_one_piece", f"{heap_kib}K", 0.1)
    assert heap_kib * 1024 - 8 * 1024 < r["free"] <= heap_kib * 1024, r
    assert r["piece"] > r["free"] - 4 * 1024, f"expected nearly all of gc.mem_free() in one bytearray: {r}"


@pytest.mark.parametrize(
    "size",
    [f'"{(HEAP_MIN_BYTES - STEP) // STEP}K"', str(HEAP_MIN_BYTES - 1)],
)
def test_one_step_below_the_least_heap_is_refused_by_check_naming_the_least(pico, size):
    path = pico / "rig.toml"
    path.write_text(GOOD.replace('entry = "main.py"', f'entry = "main.py"\n[interpreter]\nheap_size = {size}'))
    code, err = check(path)
    assert code == 2, err
    assert f"{path}: [interpreter] heap_size: expected bytes from {HEAP_MIN_BYTES // STEP}K" in err, err
    assert f"got {size}" in err or f"got '{size.strip(chr(34))}'" in err, err


def test_the_least_heap_itself_passes_check(pico):
    path = pico / "rig.toml"
    path.write_text(
        GOOD.replace('entry = "main.py"', f'entry = "main.py"\n[interpreter]\nheap_size = "{HEAP_MIN_BYTES // STEP}K"')
    )
    code, err = check(path)
    assert code == 0, err
