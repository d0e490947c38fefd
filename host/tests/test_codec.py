"""The link codec, held to one set of vectors on both ends (CPython and MicroPython)."""

import json
import struct
import subprocess
import zlib
from pathlib import Path

from host.core import interpreter
from host.shim import _hilframe as F
from host.tests.frame_vectors_check import check

HERE = Path(__file__).parent
VECTORS = HERE / "frame_vectors.json"
SHIM = HERE.parent / "shim"


def test_vectors_follow_the_documented_layout():
    """docs/protocol.md: SOF | type | seq | len u16 LE | payload | CRC-32 (zlib) of type..payload, LE."""
    for v in json.loads(VECTORS.read_text())["good"]:
        frame, payload = bytes.fromhex(v["frame"]), bytes.fromhex(v["payload"])
        assert frame[0] == 0xA5 and frame[1] == v["type"] and frame[2] == v["seq"]
        assert struct.unpack_from("<H", frame, 3)[0] == len(payload) and frame[5:-4] == payload
        assert struct.unpack("<I", frame[-4:])[0] == zlib.crc32(frame[1:-4])


def test_codec_passes_the_vectors_under_cpython():
    n, failures = check(str(VECTORS))
    assert not failures and n >= 10, failures


def test_codec_passes_the_same_vectors_under_micropython():
    out = subprocess.run(
        [str(interpreter.find()), str(HERE / "frame_vectors_check.py"), str(VECTORS)],
        env={"MICROPYPATH": f"{SHIM}:.frozen"},
        capture_output=True,
        text=True,
        timeout=30,
    )
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip().endswith("vectors, 0 failures"), out.stdout + out.stderr


def test_corrupted_frame_is_counted_and_never_delivered():
    frame = bytearray(F.encode(F.OUT, 1, struct.pack("<QHBi", 10, 3, 1, 65535)))
    for i in range(1, len(frame)):  # flip one bit anywhere after SOF: never a frame
        bad = bytearray(frame)
        bad[i] ^= 0x10
        dec = F.Decoder()
        dec.feed(bytes(bad))
        assert dec.next() is None or dec.bad_length, f"byte {i} flipped still decoded"
        while dec.pending() and dec.expire():
            assert dec.next() is None
        assert dec.frames == 0 and dec.bad_crc + dec.bad_length + dec.truncated >= 1
