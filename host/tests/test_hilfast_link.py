"""The link in C (``_hilfast.link``: the shim's frames, their CRC and a STATE's decoding, with
no allocation an exchange) encodes what ``_hilframe.encode`` encodes and takes from a byte
stream exactly the frames ``_hilframe.Decoder`` takes, with the same counts of what it
dropped, up to the first damaged frame (where the shim stops the run: LinkDamaged). The
runs of both paths, byte for byte: host/tests/test_hilfast.py."""

import random
import struct
import subprocess

import pytest

from host.core import interpreter
from host.core.paths import SHIM_DIR
from host.shim import _hilframe as F


def _has_c_link() -> bool:
    code = "import _hilfast; _hilfast.link"
    probe = subprocess.run([str(interpreter.find()), "-c", code], capture_output=True, timeout=10)
    return probe.returncode == 0


pytestmark = pytest.mark.skipif(
    not _has_c_link(), reason="this MicroPython has no _hilfast.link (a user's own interpreter: the pure path only)"
)

# In MicroPython: the C link over a file of the host's bytes, recv() until it says damaged
# (None) or the file ends (HostGone); each frame and the counters printed.
_READ = """
import sys, _hilfast
class Gone(Exception):
    pass
f = open(sys.argv[1], "rb")
link = _hilfast.link(f.fileno(), Gone)
end = "gone"
while True:
    try:
        frame = link.recv()
    except Gone:
        break
    if frame is None:
        end = "damaged"
        break
    print("frame", frame[0], frame[1], frame[2].hex() if frame[2] else "")  # (hex() of b"" is b"" here)
print(end, *link.counters())
"""

# In MicroPython: frames queued into the C link over an empty file and flushed.
_WRITE = """
import sys, _hilfast
f = open(sys.argv[1], "wb")
link = _hilfast.link(f.fileno(), Exception)
for i in range(300):
    link.queue(i % 7 + 1, bytes(range(i % 256)) * (1 + i // 100))
    if i % 50 == 0:
        link.flush()
link.flush()
"""


def _mpy(tmp_path, code, *args) -> str:
    script = tmp_path / "prog.py"
    script.write_text(code)
    env = {"MICROPYPATH": str(SHIM_DIR)}
    out = subprocess.run(
        [str(interpreter.find()), str(script), *args], capture_output=True, text=True, env=env, timeout=60
    )
    assert out.returncode == 0, f"expected the MicroPython program to run, it said: {out.stderr[-800:]}"
    return out.stdout


def _reference(data: bytes) -> list[str]:
    """What the C link should print: Decoder.next until damaged or out of frames."""
    dec = F.Decoder()
    dec.feed(data)
    lines = []
    end = "gone"
    while True:
        frame = dec.next()
        if dec.damaged:
            end = "damaged"
            break
        if frame is None:
            break
        lines.append(f"frame {frame[0]} {frame[1]} {bytes(frame[2]).hex()}")
    c = dec.counters()
    counts = (c["frames"], c["bad_crc"], c["bad_length"], c["truncated"], c["seq_gaps"], c["duplicates"])
    lines.append(" ".join(str(v) for v in (end, *counts)))
    return lines


def _stream(rng: random.Random) -> bytes:
    out = bytearray()
    seq = 0
    for _ in range(rng.randrange(1, 40)):
        n = rng.choice((0, 1, 15, 26, 251, 252, 253, 1000, 4096))
        frame = F.encode(rng.choice((F.STATE, F.EDGES, F.BUS_IMAGE, F.WELCOME)), seq, rng.randbytes(n))
        roll = rng.random()
        if roll < 0.05:  # a byte flipped: a bad CRC (or a bad length)
            k = rng.randrange(1, len(frame))
            frame = frame[:k] + bytes([frame[k] ^ (1 << rng.randrange(8))]) + frame[k + 1 :]
        elif roll < 0.1:  # the same frame again: a duplicate
            out += frame
        elif roll < 0.13:  # a frame lost: a gap in the sequence
            seq += 1
            frame = F.encode(F.STATE, seq, b"x")
        elif roll < 0.2:  # noise before it, SOF bytes and claimed lengths among it
            out += bytes(rng.choice((0xA5, 0x00, 0xFF, 0x10)) for _ in range(rng.randrange(1, 12)))
        out += frame
        seq = (seq + 1) & 0xFF
    if rng.random() < 0.3:
        out += F.encode(F.STATE, seq, b"cut short")[: rng.randrange(1, 12)]  # a partial frame at the end
    return bytes(out)


@pytest.mark.parametrize("seed", range(24))
def test_the_c_link_takes_and_counts_the_frames_the_decoder_does(tmp_path, seed):
    data = _stream(random.Random(seed))
    (tmp_path / "host.bin").write_bytes(data)
    got = _mpy(tmp_path, _READ, str(tmp_path / "host.bin")).splitlines()
    want = _reference(data)
    assert got == want, f"seed {seed}: expected the Decoder's frames and counts {want[-1]!r}, got {got[-1:]!r}"


def test_the_c_link_encodes_the_frames_the_codec_does(tmp_path):
    _mpy(tmp_path, _WRITE, str(tmp_path / "out.bin"))
    want = b"".join(F.encode(i % 7 + 1, i & 0xFF, bytes(range(i % 256)) * (1 + i // 100)) for i in range(300))
    got = (tmp_path / "out.bin").read_bytes()
    assert got == want, f"expected {len(want)} bytes as _hilframe.encode makes them, got {len(got)} that differ"


# In MicroPython: OUTs queued by the C link's out (and one it leaves to struct.pack: False).
_OUT = """
import sys, _hilfast
f = open(sys.argv[1], "wb")
link = _hilfast.link(f.fileno(), Exception)
outs = ((0, 0, 0, 1), (123456789012, 65535, 3, -5), (1, 7, 255, 2**31 - 1), (2, 8, 1, -2**31), (3, 9, 2, 65535))
for t, h, attr, value in outs:
    print(link.out(t, h, attr, value))
print(link.out(4, 1, 0, 2**70))
link.flush()
"""


def test_the_c_link_queues_an_out_as_the_shim_packs_it(tmp_path):
    outs = ((0, 0, 0, 1), (123456789012, 65535, 3, -5), (1, 7, 255, 2**31 - 1), (2, 8, 1, -(2**31)), (3, 9, 2, 65535))
    said = _mpy(tmp_path, _OUT, str(tmp_path / "out.bin")).split()
    assert said == ["True"] * len(outs) + ["False"], f"expected five OUTs queued and a big int left, got {said}"
    want = b"".join(F.encode(F.OUT, i, struct.pack(F.OUT_FMT, *o)) for i, o in enumerate(outs))
    got = (tmp_path / "out.bin").read_bytes()
    assert got == want, f"expected the OUTs as _hilframe.encode and OUT_FMT make them, got {got.hex()}"


def test_the_codes_the_c_link_spells_out_are_the_codecs():
    source = (SHIM_DIR / "cmod" / "_hilfast" / "_hilfast.c").read_text()
    for name, value in (
        ("SOF", f"0x{F.SOF:02X}"),
        ("HEADER_LEN", F.HEADER_LEN),
        ("CRC_LEN", F.CRC_LEN),
        ("MAX_PAYLOAD", F.MAX_PAYLOAD),
        ("T_OUT", f"0x{F.OUT:02X}"),
        ("OUT_LEN", struct.calcsize(F.OUT_FMT)),
        ("T_WAIT", f"0x{F.WAIT:02X}"),
        ("T_STATE", f"0x{F.STATE:02X}"),
        ("T_EDGES", f"0x{F.EDGES:02X}"),
        ("STATE_HEAD", F.STATE_LEN),
        ("WAIT_HEAD", F.WAIT_LEN),
    ):
        assert f"#define {name} {value}" in source, f"expected _hilfast.c to define {name} as {value}"
    assert F.WATCH_FMT == "<H" and struct.calcsize(F.STATE_FMT) == 26
