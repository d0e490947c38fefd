"""Processor in the loop: the shim runs on a board over its USB serial and the host's
plant serves it. Tested against a bare virtual board (the unix port's own machine
module, the flashed files in its folder)."""

import pytest

from host.device import flash, vboard
from host.device.pil import board_rig
from host.rig import Recording, RigSpec

pytestmark = pytest.mark.hil
BOARD = "esp32_devkitc"


@pytest.fixture
def flashed_board(tmp_path):
    home = tmp_path / "board"
    port = vboard.start_background(BOARD, home=home, wired=False)
    try:  # (a failed flash stops the board too)
        folder, files = flash.stage("rover", BOARD, root=tmp_path / "staged")
        flash.copy(port, folder, files)
        yield port
    finally:
        vboard.stop_background(BOARD, home)


@pytest.mark.parametrize("mode", ["lockstep", "realtime"])
def test_flashed_firmware_on_a_board_drives_the_host_plant_over_its_serial(flashed_board, tmp_path, mode):
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
    answer = flash._mpremote(flashed_board, "exec", "print(6 * 7)")
    assert "42" in answer, answer
