"""Nothing lost on the link without a word: a damaged or lost frame, in either direction,
ends the run with a link error naming the counters; a duplicated frame is dropped and the
run goes on exactly as without it. Injected on live rigs by wrapping the host's end of the
link (what the firmware writes is read through it, what the host writes goes through it)."""

import pytest

from host.core.errors import FirmwareHung, LinkDamaged
from host.device import flash, vboard
from host.device.pil import board_rig
from host.rig import Recording, RigSpec
from host.shim import _hilframe as F

pytestmark = pytest.mark.hil


class Tamper:
    """The rig's transport, with one read or write (the ``nth`` from now) changed."""

    def __init__(self, rig, direction: str, how: str, nth: int = 5):
        self.transport = rig.session.chan.transport
        self.direction, self.how, self.left = direction, how, nth
        if direction == "from_firmware":
            self.inner, self.transport.read_some = self.transport.read_some, self.read_some
        else:
            self.inner, self.transport.write = self.transport.write, self.write

    def change(self, data: bytes) -> bytes:
        frame_len = F.HEADER_LEN + int.from_bytes(data[3:5], "little") + F.CRC_LEN
        if self.how == "flip":
            return data[:6] + bytes([data[6] ^ 0x10]) + data[7:]
        if self.how == "drop":  # the first frame of this chunk never arrives
            return data[frame_len:]
        return data[:frame_len] + data  # "duplicate": the first frame twice

    def read_some(self, timeout_s):
        data = self.inner(timeout_s)
        if data[:1] == bytes([F.SOF]) and len(data) > 7:
            self.left -= 1
            if self.left == 0:
                return self.change(data)
        return data

    def write(self, data, *args):
        self.left -= 1 if data[:1] == bytes([F.SOF]) else 0
        return self.inner(self.change(data) if self.left == 0 else data, *args)


def run_tampered(make_rig, direction, how, seconds=3.0, **kw):
    rig = make_rig("rover", seed=5, trace=True, **kw)
    rig.run_for(0.5)
    Tamper(rig, direction, how)
    rig.run_for(seconds - 0.5)
    return rig


def reference_digest(make_rig, seconds=3.0):
    rig = make_rig("rover", seed=5, trace=True)
    rig.run_for(0.5)  # (the same steps: a run's end is in its trace)
    rig.run_for(seconds - 0.5)
    rig.stop()
    return rig.trace_digest


@pytest.mark.parametrize("direction", ["from_firmware", "to_firmware"])
def test_a_damaged_frame_ends_the_run_with_a_link_error_naming_the_counters(make_rig, direction):
    with pytest.raises(LinkDamaged) as err:
        run_tampered(make_rig, direction, "flip")
    text = str(err.value)
    side = "seen by the shim" if direction == "to_firmware" else "from the firmware"
    assert "bad_crc=1" in text and side in text and "artefacts:" in text and "seed: 5" in text, text


def test_a_lost_frame_from_the_firmware_ends_the_run_with_the_gap_counted(make_rig):
    with pytest.raises(LinkDamaged, match=r"seq_gaps=1") as err:
        run_tampered(make_rig, "from_firmware", "drop")
    assert "virtual t=" in str(err.value)


def test_a_lost_frame_to_the_firmware_is_reported_by_the_watchdog_with_the_link_state(make_rig):
    """A STATE that never arrives leaves the shim waiting for it: the watchdog ends the run
    in seconds and says what the host sent last."""
    with pytest.raises(FirmwareHung, match=r"last sent STATE") as err:
        run_tampered(make_rig, "to_firmware", "drop", watchdog_s=1.0)
    assert "link:" in str(err.value), str(err.value)


@pytest.mark.parametrize("direction", ["from_firmware", "to_firmware"])
def test_a_duplicated_frame_is_dropped_and_the_run_is_unchanged(make_rig, direction):
    rig = run_tampered(make_rig, direction, "duplicate")
    rig.stop()
    if direction == "from_firmware":
        assert rig.counters()["duplicates"] == 1, rig.counters()
    assert rig.trace_digest == reference_digest(make_rig), "the duplicated frame changed what the rig did"


@pytest.fixture(scope="module")
def board(tmp_path_factory):
    """One board for both directions: a run ended by a damaged frame leaves it usable, and
    the next run finds the shim already uploaded."""
    root = tmp_path_factory.mktemp("link")
    home = root / "board"
    port = vboard.start_background("esp32_devkitc", home=home, wired=False)
    try:
        folder, files = flash.stage("rover", "esp32_devkitc", root=root / "staged")
        flash.copy(port, folder, files)
        yield port
    finally:
        vboard.stop_background("esp32_devkitc", home)


@pytest.mark.parametrize("direction", ["from_firmware", "to_firmware"])
def test_a_damaged_frame_on_a_boards_serial_ends_the_run_too(board, tmp_path, direction):
    rig = board_rig(RigSpec("rover", seed=1, watchdog_s=10), Recording(artefacts=tmp_path / "pil"), port=board)
    try:
        rig.start()
        closed = []
        close = rig.target.close
        rig.target.close = lambda session_open=False: closed.append(session_open) or close(session_open)
        rig.run_for(0.5)
        Tamper(rig, direction, "flip")
        with pytest.raises(LinkDamaged, match="bad_crc=1"):
            rig.run_for(2.0)
    finally:
        rig.stop()
    # seen by the shim, the board's session ended with its FAULT and EXIT: no BYE typed at its
    # REPL (and no wait of seconds for an EXIT that came already); seen by the host, the shim
    # still waits on the link: BYE ends it
    expected = direction == "from_firmware"
    assert closed and closed[0] is expected, f"expected the board closed with session_open={expected}, got {closed}"
