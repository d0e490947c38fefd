"""Processor in the loop: the shim runs on a board over its USB serial and the host's
plant serves it. Tested against a bare virtual board (the unix port's own machine
module, the flashed files in its folder)."""

import shutil

import pytest

from host.core.paths import SHIM_DIR
from host.device import flash, vboard
from host.device.pil import board_rig
from host.rig import Recording, RigSpec

pytestmark = pytest.mark.hil
BOARD = "esp32_devkitc"


@pytest.fixture(scope="module")
def board_home(tmp_path_factory):
    return tmp_path_factory.mktemp("pil") / "board"


@pytest.fixture(scope="module")
def flashed_board(board_home):
    """One board for the module, as a user keeps theirs: the first run uploads the shim,
    the second finds it there (mpremote copies only what changed). The board holds the
    source of one shim module from an upload before the shim was compiled."""
    port = vboard.start_background(BOARD, home=board_home, wired=False)
    try:  # (a failed flash stops the board too)
        folder, files = flash.stage("rover", BOARD, root=board_home.parent / "staged")
        flash.copy(port, folder, files)
        (board_home / "fs" / "hil").mkdir(parents=True, exist_ok=True)
        shutil.copy(SHIM_DIR / "machine.py", board_home / "fs" / "hil" / "machine.py")
        yield port
    finally:
        vboard.stop_background(BOARD, board_home)


@pytest.mark.parametrize("mode", ["lockstep", "realtime"])
def test_flashed_firmware_on_a_board_drives_the_host_plant_over_its_serial(flashed_board, board_home, tmp_path, mode):
    spec = RigSpec("rover", seed=1, mode=mode, watchdog_s=10)
    rig = board_rig(spec, Recording(artefacts=tmp_path / "pil"), port=flashed_board)
    try:
        rig.start()
        x0 = rig.truth()["x_m"]
        rig.run_for(3.0 if mode == "lockstep" else 2.0)
        moved = rig.truth()["x_m"] - x0
    finally:
        rig.stop()
    assert "rover on esp32-devkitc control every 50 ms" in rig.console, rig.console
    assert moved > 0.3, f"expected the rover to drive > 0.3 m, got {moved:.3f} m; console: {rig.console[-500:]}"
    period = rig.budgets["control.period"].stats()
    if mode == "lockstep":  # virtual time: exact, whatever the board's speed
        assert period["count"] >= 59 and period["misses"] == 0 and period["max"] == 50_000, period
    else:  # the board's own clock: real periods (their jitter is a measurement)
        assert period["count"] >= 20 and period["p50"] >= 49_000, period
    counters = rig.counters()
    assert counters["bad_crc"] == 0 and counters["seq_gaps"] == 0, counters
    # the board is back at its REPL and usable
    try:
        answer = flash._mpremote(flashed_board, "exec", "print(6 * 7)")
    except flash.FlashError as e:
        log = (board_home / "vboard.log").read_text(errors="replace")[-1500:]
        raise AssertionError(
            f"expected the board back at its REPL after the {mode} session: {e}\n"
            f"the virtual board's log ({board_home / 'vboard.log'}):\n{log}\n"
            f"the session's console: {rig.console[-300:]!r}"
        ) from None
    assert "42" in answer, answer
    log = (board_home / "vboard.log").read_text()  # (what the board's console did, stamped)
    assert "plant-link session begins" in log and "plant-link session ends" in log, log[-1500:]
    assert "the interpreter soft reset (exit code 10): it boots to the raw REPL" in log, log[-1500:]
    # the shim went over compiled for the board's .mpy version, the stale source gone
    shim = board_home / "fs" / "hil"
    held = sorted(p.name for p in shim.iterdir())
    assert (shim / "_hil.mpy").is_file() and (shim / "machine.mpy").is_file(), f"expected the shim compiled: {held}"
    assert not list(shim.glob("*.py")), f"expected no shim source left beside the compiled modules: {held}"
    assert (shim / "asyncio" / "core.mpy").is_file(), sorted(p.name for p in (shim / "asyncio").iterdir())
