"""Link faults (host/link/faults.py): frames damaged at the scheduled rate in the
scheduled direction, each one caught by the codec; stalls of the scheduled length."""

import time

import pytest

from host.core.errors import LinkDamaged
from host.link import Channel
from host.link import frames as F
from host.link.faults import FaultyTransport, wrap
from sim_plant.faults import parse_faults


class Loop:
    """A transport whose writes are what its reads return, chunk by chunk."""

    def __init__(self):
        self.written: list[bytes] = []
        self.to_read: list[bytes] = []
        self.side_closed = False

    def write(self, data: bytes, timeout_s: float = 5.0) -> None:
        self.written.append(data)

    def read_some(self, timeout_s: float) -> bytes:
        return self.to_read.pop(0) if self.to_read else b""


def faults(*entries):
    return parse_faults(list(entries))


def decodes(chunk: bytes) -> bool:
    decoder = F.Decoder()
    decoder.feed(chunk)
    return decoder.next() is not None and not decoder.damaged


def test_frames_to_the_firmware_are_damaged_at_the_rate_and_every_one_is_caught():
    loop = Loop()
    chan = wrap(Channel(loop), faults({"kind": "link_corrupt", "direction": "to_firmware", "rate": 0.25}), seed=1)
    for k in range(400):
        chan.send(F.STATE, bytes(16) + k.to_bytes(2, "little"))
    bad = sum(not decodes(chunk) for chunk in loop.written)
    counted = chan.transport.counts["corrupted_to_firmware"]
    assert bad == counted, f"expected every damaged frame caught by the codec: {bad} caught, {counted} damaged"
    assert 70 <= counted <= 130, f"expected about 100 of 400 frames damaged, got {counted}"
    assert chan.transport.counts["corrupted_from_firmware"] == 0


def test_a_damaged_frame_from_the_firmware_ends_the_receive_with_link_damaged():
    loop = Loop()
    loop.to_read = [F.encode(F.WAIT, k, bytes(12)) for k in range(5)]
    chan = wrap(Channel(loop), faults({"kind": "link_corrupt", "direction": "from_firmware", "rate": 1.0}), seed=2)
    with pytest.raises(LinkDamaged, match="damaged or lost on the plant link"):
        chan.recv(0.2)
    assert chan.transport.counts["corrupted_from_firmware"] == 1


def test_stalls_hold_the_link_for_their_length_in_their_direction_only():
    loop = Loop()
    transport = FaultyTransport(
        loop, faults({"kind": "link_stall", "direction": "to_firmware", "rate": 1.0, "stall_ms": 30}), 3
    )
    t0 = time.monotonic()
    for _ in range(3):
        transport.write(b"x")
    assert transport.read_some(0.0) == b""
    took = time.monotonic() - t0
    assert took >= 0.09 and transport.counts["stalls"] == 3, (
        f"expected 3 stalls of 30 ms, got {transport.counts}, {took:.3f} s"
    )
    assert loop.written == [b"x"] * 3, "expected the bytes themselves untouched by a stall"


def test_no_link_fault_leaves_the_transport_as_it_was():
    loop = Loop()
    chan = wrap(Channel(loop), faults({"kind": "brownout", "at_s": 1}), seed=1)
    assert chan.transport is loop
