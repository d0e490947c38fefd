"""What drivers wait on, in the loop: a firmware resets an LSM6DSOX-class IMU and an
LIS3MDL-class compass as public drivers do (set BOOT / SW_RESET / REBOOT / SOFT_RST, read
the register until the chip clears the bit; micropython-lib's lsm6dsox ``reset()`` polls
CTRL3_C so) and each wait ends after the datasheet's time in virtual time; a poll that can
never end (the compass's data ready, the compass powered down) is named once in the run's
output: bus, address, register, value, since when and what the chip's model honours."""

import pytest

from host.rig.loop.rig import run_header
from host.tests.conftest import FIRMWARE, bench_app, results

pytestmark = pytest.mark.hil

MOTORS = [
    {"kind": "dc_motor", "name": "motor_l", "bridge": "tb6612", "drives": "left"},
    {"kind": "dc_motor", "name": "motor_r", "bridge": "tb6612", "drives": "right"},
]
CHIPS = {
    "body": "differential",
    "parts": [
        *MOTORS,
        {"kind": "lsm6dsox", "name": "imu", "bus": "i2c0"},
        {"kind": "lis3mdl", "name": "compass", "bus": "i2c0"},
    ],
}


def test_reset_bits_clear_after_the_datasheet_time_and_a_poll_that_never_ends_is_named_once(make_rig):
    rig = make_rig(bench_app("chip_reset_polls", CHIPS), main_dir=FIRMWARE / "chip_reset_polls", allow_exit=True)
    rig.run_for(6.0)
    rig.stop()
    r = results(rig.console)
    # each wait: the bit reads set until its time has passed, then clear (a read at 400 kHz
    # takes 70 us of virtual time: the loop sees the clear bit within a read or two of it)
    assert 10_000 <= r["boot_us"] < 10_300 and r["boot_polls"] > 50, r
    assert 50 <= r["sw_reset_us"] < 300, r
    assert 5_000 <= r["reboot_us"] < 5_300 and r["reboot_polls"] > 20, r
    assert 50 <= r["soft_rst_us"] < 300, r
    assert r["after_boot"] == 0x40 and r["after_sw_reset"] == 0x00, "BOOT keeps CTRL1_XL, SW_RESET resets it"
    assert r["gave_up_after"] > 10_000, r
    polls = [text for _t, text in rig.bus_trace.notes if "a poll that never ends" in text]
    assert len(polls) == 1, rig.bus_trace.notes
    (text,) = polls
    assert "i2c0 0x1c register 0x27" in text and "got 00 each time" in text, text
    assert "compass (Lis3mdlChip) on i2c0 at 0x1c" in text and "ZYXDA" in text and "CTRL_REG3: MD" in text, text
    assert [n["text"] for n in run_header(rig)["notes"]] == [text for _t, text in rig.bus_trace.notes]
    console_log = (rig.artefacts / "console.log").read_text()
    assert console_log.count("a poll that never ends") == 1, console_log[-2000:]
