"""A frame lost on the link, in either direction, ends the run with a message that names
the direction the link's counters show and keeps the firmware's stack (the traceback the
shim sends when the watchdog interrupts it): a frame lost from the firmware just before it
waits, a frame lost on its way to the firmware, and the firmware's HELLO lost in the
handshake (host/rig/targets/target.py, docs/reliability.md)."""

import pytest

from host.core.errors import FirmwareHung
from host.rig.loop import session
from host.rig.targets.target import UnixPortTarget, waiting_on_link
from host.shim import _hilframe as F
from host.tests.conftest import FIRMWARE, shim_app

pytestmark = pytest.mark.hil

FROM_FIRMWARE = "a frame from the firmware (firmware→host) was lost"
TO_FIRMWARE = "a frame to the firmware (host→firmware) was lost"


def frames_in(data: bytes) -> list[tuple[int, int, int]]:
    """(start, end, type) of each whole frame in a chunk that starts with one."""
    out, i = [], 0
    while i + F.HEADER_LEN <= len(data) and data[i] == F.SOF:
        end = i + F.HEADER_LEN + int.from_bytes(data[i + 3 : i + 5], "little") + F.CRC_LEN
        out.append((i, end, data[i + 1]))
        i = end
    return out


class LoseOne:
    """One frame of a live rig's link lost, the ``nth`` of its kind from now: from the
    firmware, its WAIT (the frame it sends just before it waits); to the firmware, a STATE."""

    def __init__(self, transport, direction: str, nth: int = 20):
        self.left, self.lost = nth, None
        if direction == "from_firmware":
            self.inner, transport.read_some = transport.read_some, self.read_some
        else:
            self.inner, transport.write = transport.write, self.write

    def read_some(self, timeout_s):
        data = self.inner(timeout_s)
        frames = frames_in(data)
        if frames and frames[-1][2] == F.WAIT and self.lost is None:
            self.left -= 1
            if self.left == 0:
                start, _end, self.lost = frames[-1]
                return data[:start]
        return data

    def write(self, data, *args):
        if data[1:2] == bytes([F.STATE]) and self.lost is None:
            self.left -= 1
            if self.left == 0:
                self.lost = F.STATE
                return None
        return self.inner(data, *args)


def hung_run(make_rig, direction: str) -> str:
    rig = make_rig(shim_app(), main_dir=FIRMWARE / "ping", watchdog_s=1.0)
    rig.run_for(0.01)
    loss = LoseOne(rig.session.chan.transport, direction)
    with pytest.raises(FirmwareHung) as err:
        rig.run_for(1.0)
    assert loss.lost is not None, "expected a frame lost"
    return str(err.value)


def test_a_frame_lost_from_the_firmware_before_it_waits_is_named_so_with_its_stack(make_rig):
    text = hung_run(make_rig, "from_firmware")
    assert FROM_FIRMWARE in text and "seq_gaps=1" in text, text
    assert TO_FIRMWARE not in text and "on its way to the firmware" not in text, text
    assert "KeyboardInterrupt" in text and waiting_on_link(text), f"expected the firmware's stack: {text}"
    assert "main.py" in text, f"expected the stack down to the firmware's line: {text}"


def test_a_frame_lost_on_its_way_to_the_firmware_is_named_so_with_its_stack(make_rig):
    text = hung_run(make_rig, "to_firmware")
    assert TO_FIRMWARE in text and "last sent STATE" in text, text
    assert "seq_gaps" not in text and FROM_FIRMWARE not in text, text
    assert "KeyboardInterrupt" in text and waiting_on_link(text), f"expected the firmware's stack: {text}"


class HelloLost(UnixPortTarget):
    """The unix port, with the firmware's first frame (HELLO) lost on the link."""

    def open(self, firmware, on_console):
        chan = super().open(firmware, on_console)
        transport, inner = chan.transport, chan.transport.read_some

        def read_some(timeout_s):
            data = inner(timeout_s)
            frames = frames_in(data)
            if frames and frames[0][2] == F.HELLO:
                return data[frames[0][1] :]
            return data

        transport.read_some = read_some
        return chan


def test_a_hello_lost_in_the_handshake_is_named_as_lost_from_the_firmware(make_rig, monkeypatch):
    monkeypatch.setattr(session, "HANDSHAKE_TIMEOUT_S", 1.0)
    with pytest.raises(FirmwareHung) as err:
        make_rig(shim_app(), main_dir=FIRMWARE / "ping", target=HelloLost())  # (started: the handshake)
    text = str(err.value)
    assert "expected HELLO" in text and "HELLO, firmware→host) was lost" in text, text
    assert "on its way to the firmware" not in text and "host→firmware" not in text, text
    assert "KeyboardInterrupt" in text and "in start" in text, f"expected the shim's stack in its handshake: {text}"
