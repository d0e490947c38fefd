# Checks the frame codec against host/tests/frame_vectors.json. Runs unchanged under
# CPython (imported by test_codec.py) and MicroPython (run as a script), so both ends
# of the link are held to the same bytes.
import json

try:
    from host.shim import _hilframe as F
except ImportError:  # MicroPython: the shim folder is on MICROPYPATH
    import _hilframe as F


def unhex(text):
    return bytes(int(text[i : i + 2], 16) for i in range(0, len(text), 2))


def plain(value):
    """JSON fields as the codec takes them: {"hex": ...} is bytes, lists stay lists, any
    other dict (WELCOME's settings) is a dict of plain fields."""
    if isinstance(value, dict):
        if list(value) == ["hex"]:
            return unhex(value["hex"])
        return {key: plain(v) for key, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    return value


def check_message(v):
    """pack_<message>(fields) gives the payload; unpack_<message>(payload) the fields
    (HELLO and WELCOME lead with the protocol version, which pack adds)."""
    name = v["message"]
    fields = plain(v["fields"])
    payload = unhex(v["payload"])
    args = fields
    if name == "state":
        args = fields[:3] + [[tuple(c) for c in fields[3]]]
    failures = []
    if getattr(F, "pack_" + name)(*args) != payload:
        failures.append("pack " + name)
    want = [F.PROTO_VERSION] + fields if name in ("hello", "welcome") else fields
    if plain(getattr(F, "unpack_" + name)(payload)) != want:
        failures.append("unpack " + name)
    return failures


def decode_all(stream):
    dec = F.Decoder()
    dec.feed(stream)
    out = []
    while True:
        frame = dec.next()
        if frame is None:
            if dec.pending() and dec.expire():  # the rest never comes: a truncated frame
                continue
            return out, dec
        out.append(frame)


def check(path):
    with open(path) as f:
        vectors = json.load(f)
    by_name = {}
    failures = []
    for v in vectors["good"]:
        payload, frame = unhex(v["payload"]), unhex(v["frame"])
        by_name[v["name"]] = (v["type"], v["seq"], payload)
        if F.encode(v["type"], v["seq"], payload) != frame:
            failures.append("encode " + v["name"])
        got, dec = decode_all(frame)
        if [(t, s, bytes(p)) for t, s, p in got] != [(v["type"], v["seq"], payload)]:
            failures.append("decode " + v["name"])
    for v in vectors["streams"]:
        got, dec = decode_all(unhex(v["stream"]))
        want = [by_name[n] for n in v["frames"]]
        if [(t, s, bytes(p)) for t, s, p in got] != want:
            failures.append("stream frames " + v["name"])
        counters = dec.counters()
        for key, value in v["counters"].items():
            if counters[key] != value:
                failures.append("stream %s: %s=%d, expected %d" % (v["name"], key, counters[key], value))
    for v in vectors["messages"]:
        failures += check_message(v)
    return len(vectors["good"]) + len(vectors["streams"]) + len(vectors["messages"]), failures


if __name__ == "__main__":
    import sys

    n, failures = check(sys.argv[1] if len(sys.argv) > 1 else "frame_vectors.json")
    for failure in failures:
        print("FAIL", failure)
    print("checked", n, "vectors,", len(failures), "failures")
