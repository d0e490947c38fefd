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
    return len(vectors["good"]) + len(vectors["streams"]), failures


if __name__ == "__main__":
    import sys

    n, failures = check(sys.argv[1] if len(sys.argv) > 1 else "frame_vectors.json")
    for failure in failures:
        print("FAIL", failure)
    print("checked", n, "vectors,", len(failures), "failures")
