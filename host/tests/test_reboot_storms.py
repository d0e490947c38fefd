"""A reboot storm at any rate ends the run within seconds of wall time, naming the resets
and their rate; a board that resets rarely (a watchdog every few minutes) runs on
(host/rig/loop/endings.py, docs/reliability.md)."""

import re
import shutil
import time

import pytest

from host.core.errors import FirmwareError
from host.rig.loop.endings import STORM_RESETS
from host.tests.conftest import FIRMWARE, shim_app

pytestmark = pytest.mark.hil

WALL_LIMIT_S = 10.0


def storm_firmware(tmp_path, retry_ms: int):
    folder = tmp_path / f"storm_{retry_ms}ms"
    shutil.copytree(FIRMWARE / "reboot_storm", folder)
    (folder / "config.py").write_text(f"RETRY_MS = {retry_ms}\n")
    return folder


@pytest.mark.parametrize("retry_ms", [0, 2, 50, 300])
def test_a_reboot_storm_at_any_rate_ends_in_seconds_naming_its_resets_and_rate(make_rig, tmp_path, retry_ms):
    rig = make_rig(shim_app(), main_dir=storm_firmware(tmp_path, retry_ms))
    start = time.monotonic()
    with pytest.raises(FirmwareError, match=f"reboot storm: the firmware reset {STORM_RESETS} times") as err:
        rig.run_for(3600)
    took_s = time.monotonic() - start
    text = str(err.value)
    assert took_s < WALL_LIMIT_S, (
        f"expected the storm stopped within {WALL_LIMIT_S:g} s of wall time, took {took_s:.1f} s"
    )
    assert rig.resets == STORM_RESETS - 1, f"expected the run stopped at the storm's {STORM_RESETS}th reset: {text}"
    assert rig.console.count("boot") == STORM_RESETS
    if retry_ms == 0:
        assert "at one instant of virtual time" in text, text
    else:
        rate = float(re.search(r"\(([\d.e+]+) resets per virtual second", text).group(1))
        expected = 1000 / retry_ms
        assert abs(rate - expected) / expected < 0.01, f"expected about {expected:g} resets per virtual second: {text}"
    assert "seed:" in text and "console (last" in text, text


def test_a_board_reset_by_its_watchdog_every_few_minutes_is_let_run(make_rig):
    rig = make_rig(shim_app(), main_dir=FIRMWARE / "watchdog_rare")
    rig.run_for(12 * 130 + 5)
    rig.stop()
    assert rig.resets == 12, f"expected a reset every 130 s of virtual time, got {rig.resets}:\n{rig.console[-500:]}"
    assert rig.resets > STORM_RESETS, "as many resets as a storm's, but rare: no storm"
