"""The link drops what is corrupted and never acts on it."""

import os
import struct

import pytest

from host.shim import _hilframe as F

pytestmark = pytest.mark.hil


def test_corrupted_frame_from_the_firmware_side_is_counted_and_ignored(make_rig):
    reference = make_rig("rover", seed=5, trace=True)
    reference.run_for(3)
    reference.stop()

    rig = make_rig("rover", seed=5, trace=True)
    rig.run_for(1)
    # a full-throttle command on the left motor's PWM (handle 2), with one bit flipped
    bad = bytearray(F.encode(F.OUT, 0, struct.pack("<QHBi", rig.t_us, 2, F.OUT_DUTY, 65535)))
    bad[8] ^= 0x04
    os.write(rig.target.pty.slave_fd, bytes(bad) + b"\x00noise")
    rig.run_for(2)
    rig.stop()
    counters = rig.counters()
    assert counters["bad_crc"] == 1 and counters["skipped_bytes"] >= 6, counters
    assert rig.trace_digest == reference.trace_digest, "the corrupted frame changed what the rig did"
