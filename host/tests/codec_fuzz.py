# A long fuzz run of the frame codec (host/shim/_hilframe.py) that runs unchanged under
# CPython and MicroPython, for `make fuzz`:
#
#   python -m host.tests.codec_fuzz [--seconds S | --cases N] [--seed K]
#   MICROPYPATH=.frozen micropython host/tests/codec_fuzz.py [--seconds S | --cases N] [--seed K]
#   ... --resync: the time to decode 64 KiB of adversarial start bytes (docs/reliability.md)
#
# Each case is a stream built from a seeded generator (the same cases on both interpreters):
# noise, good frames among garbage, good frames with one of them damaged (a bit flipped, its
# tail cut, bytes inserted or taken out), and adversarial runs of start bytes claiming long
# frames; it is fed in pieces of random sizes, and in half the cases a partial frame expires
# at random on the way (a stalled link). Checked: nothing raises, no frame comes out that was
# not sent whole (a damaged frame accepted), every good frame is found (with no stall; with
# stalls, those found are in order), and every byte is counted. The last line sums it up; the exit
# status is 1 if any case failed. The bounded property tests are test_codec_properties.py.
import sys
import time

if sys.implementation.name == "micropython":
    # the shim's folder holds a `time` of its own: imported above first, then the codec
    sys.path.append(sys.argv[0].rsplit("/", 2)[0] + "/shim")
    import _hilframe as F

    def now_us():
        return time.ticks_us()

    def elapsed_us(t0):
        return time.ticks_diff(time.ticks_us(), t0)

else:
    from host.shim import _hilframe as F

    def now_us():
        return time.perf_counter_ns() // 1000

    def elapsed_us(t0):
        return now_us() - t0


KINDS = ("noise", "garbage", "damaged", "adversarial")


class Rand:
    """xorshift32: the same numbers on both interpreters (small ints on a 64-bit build)."""

    def __init__(self, seed):
        self.x = (seed * 2654435761 + 1) & 0xFFFFFFFF or 1

    def next(self):
        x = self.x
        x ^= (x << 13) & 0xFFFFFFFF
        x ^= x >> 17
        x ^= (x << 5) & 0xFFFFFFFF
        self.x = x
        return x

    def below(self, n):
        return self.next() % n

    def bytes(self, n):
        return bytes(self.next() & 0xFF for _ in range(n))

    def junk(self, n):
        """Bytes rich in start bytes and small lengths, or plain random bytes."""
        if self.below(2):
            return self.bytes(n)
        pick = (0xA5, 0x00, 0x10, 0x01, 0x0F, 0xFF)
        return bytes(pick[self.below(6)] for _ in range(n))


def good_frames(r, count):
    seq = r.below(256)
    frames = []
    for k in range(count):
        size = r.below(48) if r.below(8) else r.below(F.MAX_PAYLOAD + 1)
        frames.append((r.below(256), (seq + k) & 0xFF, r.bytes(size)))
    return frames


def damage(r, frame):
    frame = bytearray(frame)
    how = r.below(4)
    if how == 0:
        bit = r.below(len(frame) * 8)
        frame[bit // 8] ^= 1 << (bit % 8)
    elif how == 1:
        frame = frame[: len(frame) - 1 - r.below(len(frame) - 1)]
    elif how == 2:
        at = 1 + r.below(len(frame) - 1)
        frame = frame[:at] + r.bytes(1 + r.below(8)) + frame[at:]
    else:
        at = 1 + r.below(len(frame) - 2)
        frame = frame[:at] + frame[at + 1 + r.below(min(8, len(frame) - 1 - at)) :]
    return bytes(frame)


def make_case(r, kind):
    """(stream, frames expected out of it)."""
    if kind == "noise":
        return r.junk(r.below(2000)), None
    if kind == "garbage":
        frames = good_frames(r, 1 + r.below(6))
        parts = [r.junk(r.below(64))]
        for f in frames:
            parts += [F.encode(*f), r.junk(r.below(64))]
        return b"".join(parts), frames
    if kind == "damaged":
        frames = good_frames(r, 1 + r.below(5))
        k = r.below(len(frames))
        parts = [F.encode(*f) for f in frames]
        parts[k] = damage(r, parts[k])
        return b"".join(parts), frames[:k] + frames[k + 1 :]
    claim = F.MAX_PAYLOAD - r.below(64)  # start bytes claiming long frames, then a good one
    head = bytes((F.SOF, F.OUT, 0, claim & 0xFF, claim >> 8))
    frames = good_frames(r, 1) if r.below(2) else [(r.below(256), r.below(256), r.bytes(claim))]  # (as long)
    return head * (1 + r.below(2000)) + F.encode(*frames[0]), frames


def decode(r, stream, stalls):
    """Fed in random pieces; a partial frame expires at the end and, if ``stalls``, at
    random on the way (the link stalled in the middle of a frame: that frame is lost)."""
    dec = F.Decoder()
    out = []
    pos = 0
    while True:
        frame = dec.next()
        if frame is not None:
            out.append((frame[0], frame[1], bytes(frame[2])))
            continue
        if dec.pending() and (pos >= len(stream) or (stalls and r.below(8) == 0)):
            dec.expire()
            continue
        if pos >= len(stream):
            return out, dec
        n = 1 + r.below(700) if r.below(2) else 1 + r.below(16)
        dec.feed(stream[pos : pos + n])
        pos += n


def subsequence(got, sent):
    it = iter(sent)
    return all(any(frame == s for s in it) for frame in got)


def check(stream, expected, stalls, got, dec):
    """What is wrong with a case: a list of (tally, text). A stall may lose good frames,
    never add one or change their order."""
    wrong = []
    sent = expected if expected is not None else []
    for frame in got:
        if frame not in sent:
            wrong.append(("accepted", "a frame that was not sent whole: %r" % (frame[:2],)))
    if expected is not None and (not subsequence(got, sent) if stalls else got != expected):
        wrong.append(("missed", "expected %d good frames in order, got %d" % (len(expected), len(got))))
    c = dec.counters()
    framed = sum(F.HEADER_LEN + len(p) + F.CRC_LEN for _, _, p in got)
    counted = c["skipped_bytes"] + framed + c["bad_crc"] + c["bad_length"] + c["truncated"]
    if counted != len(stream) or c["frames"] != len(got):
        wrong.append(("counters", "%d of %d bytes counted, counters %r" % (counted, len(stream), c)))
    return wrong


def run(seconds, cases, seed):
    tally = {"cases": 0, "bytes": 0, "exceptions": 0, "accepted": 0, "missed": 0, "counters": 0}
    first = []
    slowest = (0, None, None, 0)
    t_start = now_us()
    i = 0
    while (cases and i < cases) or (not cases and elapsed_us(t_start) < seconds * 1_000_000):
        r = Rand(seed * 1_000_003 + i)
        kind = KINDS[r.below(len(KINDS))]
        stream, expected = make_case(r, kind)
        stalls = r.below(2) == 0
        t0 = now_us()
        try:
            got, dec = decode(r, stream, stalls)
            wrong = check(stream, expected, stalls, got, dec)
        except Exception as e:  # noqa: BLE001 (a fuzzer counts whatever is raised)
            wrong = [("exceptions", "%s: %s" % (type(e).__name__, e))]
        took = elapsed_us(t0)
        if took > slowest[0]:
            slowest = (took, i, kind, len(stream))
        for key, text in wrong:
            tally[key] += 1
            if len(first) < 5:
                first.append("case %d (%s, seed %d): %s" % (i, kind, seed, text))
        tally["cases"] += 1
        tally["bytes"] += len(stream)
        i += 1
    wall = elapsed_us(t_start) / 1e6
    return tally, first, slowest, wall


def resync_ms(read_size):
    """Milliseconds (best of 3) to decode 64 KiB of start bytes that each claim a
    4096-byte frame (SOF, OUT, seq 0, length 4096, over and over: every fifth byte a false
    start whose CRC spans 4 KiB), fed in reads of ``read_size`` bytes."""
    head = bytes((F.SOF, F.OUT, 0, F.MAX_PAYLOAD & 0xFF, F.MAX_PAYLOAD >> 8))
    stream = (head * (65536 // len(head) + 1))[:65536]
    best = None
    for _ in range(3):
        t0 = now_us()
        dec = F.Decoder()
        for at in range(0, len(stream), read_size):
            dec.feed(stream[at : at + read_size])
            while dec.next() is not None:
                pass
        while dec.pending():
            while dec.next() is not None:
                pass
            dec.expire()
        took = elapsed_us(t0) / 1000
        best = took if best is None or took < best else best
    return best


def main(argv):
    seconds, cases, seed = 10.0, 0, 1
    args = list(argv)
    while args:
        flag = args.pop(0)
        if flag == "--seconds":
            seconds = float(args.pop(0))
        elif flag == "--cases":
            cases = int(args.pop(0))
        elif flag == "--seed":
            seed = int(args.pop(0))
        elif flag == "--resync":
            print(
                "adversarial resync, 64 KiB of start bytes claiming 4096-byte frames: %.0f ms fed whole, "
                "%.0f ms in 16-byte reads" % (resync_ms(65536), resync_ms(16))
            )
            return 0
        else:
            print("usage: codec_fuzz [--seconds S | --cases N] [--seed K] | --resync; unknown %r" % flag)
            return 2
    tally, first, slowest, wall = run(seconds, cases, seed)
    impl = sys.implementation
    name = "%s %s" % (impl.name, ".".join(str(v) for v in impl.version[:3]))
    for line in first:
        print("  " + line)
    print(
        "codec fuzz on %s, seed %d: %d cases (%d bytes) in %.1f s, %d cases/s; %d exceptions, "
        "%d damaged frames accepted, %d good frames missed, %d counter mismatches; "
        "slowest case #%s (%s, %d bytes) %.1f ms"
        % (
            name,
            seed,
            tally["cases"],
            tally["bytes"],
            wall,
            tally["cases"] / wall if wall else 0,
            tally["exceptions"],
            tally["accepted"],
            tally["missed"],
            tally["counters"],
            slowest[1],
            slowest[2],
            slowest[3],
            slowest[0] / 1000,
        )
    )
    failed = tally["exceptions"] + tally["accepted"] + tally["missed"] + tally["counters"]
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
