"""The link codec, held to one set of vectors on both ends (CPython and MicroPython)."""

import json
import struct
import subprocess
import sys
import zlib
from pathlib import Path

from host.core import interpreter
from host.shim import _hilframe as F
from host.shim import _hilpio
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


TYPE_CODES = {"u8": "B", "u16": "H", "u32": "I", "u64": "Q", "i32": "i", "i64": "q", "f64": "d"}
# what follows the fixed part
# (I2CT_DONE's row draws the transaction it answers too: the target's CH_BYTES change)
SECOND_PART = {
    "WELCOME": "WELCOME_SETTINGS_FMT",
    "WAIT": "WATCH_FMT",
    "STATE": "CHANGE_FMT",
    "BUS_IMAGE": "BUS_IMAGE_ENTRY_FMT",
    "I2CT_DONE": "I2CT_XACT_FMT",
    "CPU_RUNS": "CPU_RUN_FMT",
    "EDGES": "EDGE_SEG_FMT",
    "PIO_AHEAD": "PIO_AHEAD_ENTRY_FMT",
}


def documented_layouts() -> dict[str, str]:
    """docs/protocol.md's message table as struct formats: each backticked field list of
    a row (`u64 t, u16 handle, ...`) is one format."""
    import re

    layouts = {}
    table = (HERE.parent.parent / "docs" / "protocol.md").read_text()
    for row in re.findall(r"^\| 0x[0-9a-f]{2} \| (\w+) \|[^|]*\|(.*)\|$", table, flags=re.M):
        name, payload = row
        parts = [re.findall(r"\b([uif]\d+)\b", seg) for seg in re.findall(r"`([^`]*)`", payload)]
        formats = ["<" + "".join(TYPE_CODES[t] for t in p) for p in parts if p]
        if formats:
            layouts[f"{name}_FMT"] = formats[0]
        if len(formats) > 1:
            layouts[SECOND_PART[name]] = formats[1]
    return layouts


def test_codec_message_layouts_are_the_ones_docs_protocol_md_draws():
    layouts = documented_layouts()
    assert len(layouts) == 29, sorted(layouts)  # 21 messages with a payload, and the 8 second parts above
    for name, fmt in layouts.items():
        codec = F if hasattr(F, name) else _hilpio  # (PIO_AHEAD's and PIO_DONE's: rp2.py's alone)
        got = getattr(codec, name)
        assert got == fmt, f"{name}: docs/protocol.md draws {fmt}, the codec has {got}"


def test_state_helper_sends_times_before_the_base_as_the_base():
    payload = F.pack_state(1000, 2000, 3000, [(900, 1, F.CH_LEVEL, 1, 0), (1500, 2, F.CH_SAMPLE, 7, 4)])
    assert F.unpack_state(payload) == (1000, 2000, 3000, [(1000, 1, F.CH_LEVEL, 1, 0), (1500, 2, F.CH_SAMPLE, 7, 4)])


def test_fault_helper_keeps_the_end_of_a_traceback_too_long_for_one_frame():
    text = b"Traceback (most recent call last):\n" + b'  File "main.py", line 1\n' * 400 + b"ValueError: the cause\n"
    t_us, kept = F.unpack_fault(F.pack_fault(5, text))
    assert t_us == 5 and kept.endswith(b"ValueError: the cause\n") and len(kept) == F.MAX_PAYLOAD - F.FAULT_LEN


def test_the_hosts_compiled_helpers_give_the_codecs_bytes_on_every_vector():
    from host.link import frames

    for v in json.loads(VECTORS.read_text())["messages"]:
        payload = bytes.fromhex(v["payload"])
        if v["message"] == "out":
            assert frames.unpack_out(payload) == F.unpack_out(payload)
        if v["message"] == "seen":
            assert frames.unpack_seen(payload) == F.unpack_seen(payload)
        if v["message"] == "uart_tx":
            head = frames.unpack_uart_tx_head(payload)
            assert head + (bytes(payload[F.UART_TX_LEN :]),) == F.unpack_uart_tx(payload)
        if v["message"] == "wait":
            if len(payload) < frames.WAIT_NO_WATCH_BELOW:
                assert frames.unpack_wait_head(payload) + ((),) == F.unpack_wait(payload)
            else:
                assert F.unpack_wait(payload)[3], f"a WAIT of {len(payload)} bytes watches a handle"
        if v["message"] == "state":
            base, t_end, horizon, changes = F.unpack_state(payload)
            assert frames.pack_state(base, t_end, horizon, changes) == F.pack_state(base, t_end, horizon, changes)
            assert frames.pack_state(base, t_end, horizon, changes) == payload
    for v in json.loads(VECTORS.read_text())["good"]:
        payload = bytes.fromhex(v["payload"])
        assert frames.encode(v["type"], v["seq"], payload).hex() == v["frame"]
    for n in (0, 1, 251, 252, 4096):
        payload = bytes(range(256)) * (n // 256) + bytes(n % 256)
        assert frames.encode(0x42, 300, payload) == F.encode(0x42, 300, payload)
    reply = frames.pack_bus_reply_head(123456, 1, 2, 123789) + b"\x0c\x00"
    assert reply == F.pack_bus_reply(123456, 1, 2, 123789, b"\x0c\x00")


def test_the_fuzzer_of_make_fuzz_runs_its_cases_on_both_interpreters():
    """A few hundred cases of host/tests/codec_fuzz.py (make fuzz runs it for minutes)
    under CPython and MicroPython: same cases, none failing."""
    here = [sys.executable, "-m", "host.tests.codec_fuzz", "--cases", "300"]
    there = [str(interpreter.find()), str(HERE / "codec_fuzz.py"), "--cases", "300"]
    for command, env in ((here, None), (there, {"MICROPYPATH": ".frozen"})):
        out = subprocess.run(command, cwd=HERE.parent.parent, env=env, capture_output=True, text=True, timeout=120)
        summary = out.stdout.strip().splitlines()[-1] if out.stdout.strip() else out.stderr
        assert out.returncode == 0, f"{command[0]}: exit {out.returncode}, expected 0:\n{out.stdout}{out.stderr}"
        assert (
            ": 300 cases" in summary and "0 exceptions, 0 damaged frames accepted, 0 good frames missed" in summary
        ), summary
