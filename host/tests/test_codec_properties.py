"""Property-based tests of the frame codec (host/shim/_hilframe.py) under CPython, with
hypothesis: any byte stream decodes without raising and every byte is accounted for; a
damaged frame is never taken for another frame; good frames among garbage are all
found; and the decoder takes exactly what the decoder before its cheaper resync took.
Bounded (a few seconds) and derandomized: the same examples on every run. ``make fuzz``
runs the long version on CPython and MicroPython (host/tests/codec_fuzz.py)."""

import struct

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from host.link.frames import HostDecoder
from host.shim import _hilframe as F

SETTINGS = settings(
    max_examples=250,
    derandomize=True,
    database=None,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)


class ReferenceDecoder:
    """The decoder as it was before its resync was made cheap (a rescan of the rest of
    the buffer with copies at each feed and each false start): what it accepts and
    counts is the reference the codec's decoder must keep."""

    def __init__(self):
        self.buf = b""
        self.pos = 0
        self.frames = self.bad_crc = self.bad_length = self.truncated = self.skipped = self.seq_gaps = 0
        self.duplicates = 0
        self.expect_seq = -1
        self.on_skip = None

    def feed(self, data):
        if self.pos:
            self.buf = self.buf[self.pos :]
            self.pos = 0
        self.buf += bytes(data)

    def pending(self):
        return len(self.buf) - self.pos

    def next(self):
        buf = self.buf
        while True:
            i = buf.find(b"\xa5", self.pos)
            end_skip = len(buf) if i < 0 else i
            if end_skip > self.pos:
                self.skipped += end_skip - self.pos
                if self.on_skip is not None:
                    self.on_skip(buf[self.pos : end_skip])
            if i < 0:
                self.pos = len(buf)
                return None
            self.pos = i
            if len(buf) - i < F.HEADER_LEN:
                return None
            type_, seq, n = struct.unpack_from("<BBH", buf, i + 1)
            if n > F.MAX_PAYLOAD:
                self.bad_length += 1
                self.pos = i + 1
                continue
            end = i + F.HEADER_LEN + n
            if len(buf) < end + F.CRC_LEN:
                return None
            (crc,) = struct.unpack_from("<I", buf, end)
            if F.crc32(buf[i + 1 : end]) & 0xFFFFFFFF != crc:
                self.bad_crc += 1
                self.pos = i + 1
                continue
            self.pos = end + F.CRC_LEN
            if self.expect_seq >= 0 and seq != self.expect_seq:
                if seq == (self.expect_seq - 1) & 0xFF:  # the same frame again: dropped
                    self.duplicates += 1
                    continue
                self.seq_gaps += 1
            self.frames += 1
            self.expect_seq = (seq + 1) & 0xFF
            return type_, seq, buf[i + F.HEADER_LEN : end]

    def expire(self):
        if self.pending() == 0:
            return False
        self.truncated += 1
        self.pos += 1
        return True

    counters = F.Decoder.counters


def decode(dec, pieces, expire_when_stuck=None):
    """Feed ``pieces`` one at a time, taking every frame after each; when no frame is
    complete, drop the partial frame (expire) if ``expire_when_stuck`` says so (a list
    of booleans, used in turn; None: never) and at the end until nothing is pending,
    as a link's truncation timeout does. Returns the frames, each payload bytes."""
    out = []
    choices = iter(expire_when_stuck or ())

    def drain(final):
        while True:
            frame = dec.next()
            if frame is not None:
                assert type(frame[2]) is bytes, f"expected a payload as bytes, got {type(frame[2]).__name__}"
                out.append(frame)
            elif dec.pending() and (final or next(choices, False)):
                dec.expire()
            else:
                return

    for piece in pieces:
        dec.feed(piece)
        drain(False)
    drain(True)
    return out


def split(data: bytes, cuts: list[int]) -> list[bytes]:
    """``data`` in pieces at the given offsets (taken modulo its length, any order)."""
    points = sorted({c % (len(data) + 1) for c in cuts} | {0, len(data)})
    return [data[a:b] for a, b in zip(points, points[1:])] or [b""]


def frame_bytes(frames) -> int:
    return sum(F.HEADER_LEN + len(p) + F.CRC_LEN for _, _, p in frames)


# -- strategies ---------------------------------------------------------------------------

payloads = st.one_of(st.binary(max_size=40), st.binary(min_size=200, max_size=700))
sof_heavy = st.lists(st.sampled_from([0xA5, 0x00, 0x10, 0x01, 0xFF, 0x0F]), max_size=80).map(bytes)
garbage = st.one_of(st.binary(max_size=60), sof_heavy)
cuts = st.lists(st.integers(0, 10_000), max_size=12)


@st.composite
def good_frames(draw, min_size=1, max_size=6):
    """Frames with consecutive sequence numbers, as one direction of the link sends them."""
    n = draw(st.integers(min_size, max_size))
    seq0 = draw(st.integers(0, 255))
    return [(draw(st.integers(0, 255)), (seq0 + k) & 0xFF, draw(payloads)) for k in range(n)]


def adversarial_header(claim: int) -> bytes:
    """An SOF and a header that claim a ``claim``-byte payload, and nothing more."""
    return bytes([F.SOF, F.OUT, 0]) + struct.pack("<H", claim)


@st.composite
def attacks(draw):
    """Start bytes claiming one length over and over (enough of them for the decoder to
    share their CRC work), with garbage and good frames among them, some of the very
    length claimed (a good frame checked through the shared work)."""
    claim = draw(st.integers(252, 700))
    parts = []
    for _ in range(draw(st.integers(1, 4))):
        parts.append(adversarial_header(claim) * draw(st.integers(1, 60)))
        good = (draw(st.integers(0, 255)), draw(st.integers(0, 255)), draw(st.binary(min_size=claim, max_size=claim)))
        parts.append(draw(st.one_of(garbage, st.just(F.encode(*good)))))
    return b"".join(parts)


streams = st.one_of(
    st.binary(max_size=1500),
    attacks(),
    st.lists(
        st.one_of(
            good_frames(1, 2).map(lambda fs: b"".join(F.encode(*f) for f in fs)),
            garbage,
            st.integers(0, 4200).map(adversarial_header),
        ),
        max_size=10,
    ).map(b"".join),
)


# -- properties ---------------------------------------------------------------------------


@SETTINGS
@given(streams, cuts)
def test_any_byte_stream_decodes_without_raising_and_every_byte_is_accounted_for(stream, at):
    dec = F.Decoder()
    frames = decode(dec, split(stream, at))
    c = dec.counters()
    accounted = c["skipped_bytes"] + frame_bytes(frames) + c["bad_crc"] + c["bad_length"] + c["truncated"]
    accounted += dec.duplicate_bytes  # (frames sent twice: the second dropped whole)
    assert c["frames"] == len(frames), c
    assert dec.pending() == 0 and accounted == len(stream), (
        f"expected every one of {len(stream)} bytes in a frame, skipped, or the start of a dropped frame; "
        f"got {accounted} ({len(frames)} frames of {frame_bytes(frames)} bytes, counters {c}) "
        f"for stream {stream.hex()}"
    )


@SETTINGS
@given(streams, cuts, st.lists(st.booleans(), max_size=20))
def test_the_decoder_takes_and_counts_what_the_reference_decoder_does(stream, at, expire_when_stuck):
    """The cheaper resync changes no outcome: the same frames, the same counters and the
    same bytes outside frames, however the stream is cut and whenever partial frames expire."""
    shared = F.Decoder()
    shared.share_after = 16  # (MicroPython's default; CPython's is None)
    runs = []
    for dec in (F.Decoder(), shared, ReferenceDecoder(), HostDecoder()):
        skipped = []
        dec.on_skip = lambda b, skipped=skipped: skipped.append(bytes(b))
        frames = decode(dec, split(stream, at), list(expire_when_stuck))
        runs.append((frames, dec.counters(), b"".join(skipped)))
    assert runs[0] == runs[1] == runs[2] == runs[3], (
        f"decoder {runs[0]}\nsharing {runs[1]}\nreference {runs[2]}\nthe host's {runs[3]}\n"
        f"for stream {stream.hex()} cut at {at}"
    )


@st.composite
def damaged_streams(draw):
    """(good frames, index of the damaged one, the stream with it damaged): one bit flipped,
    its tail cut off, bytes inserted into it or bytes taken out of it."""
    frames = draw(good_frames(1, 5))
    k = draw(st.integers(0, len(frames) - 1))
    encoded = [F.encode(*f) for f in frames]
    frame = bytearray(encoded[k])
    how = draw(st.sampled_from(["flip", "truncate", "insert", "delete"]))
    if how == "flip":
        bit = draw(st.integers(0, len(frame) * 8 - 1))
        frame[bit // 8] ^= 1 << (bit % 8)
    elif how == "truncate":
        del frame[len(frame) - draw(st.integers(1, len(frame) - 1)) :]
    elif how == "insert":
        at = draw(st.integers(1, len(frame) - 1))
        frame[at:at] = draw(st.binary(min_size=1, max_size=8))
    else:
        at = draw(st.integers(1, len(frame) - 2))
        del frame[at : at + draw(st.integers(1, min(8, len(frame) - 1 - at)))]
    encoded[k] = bytes(frame)
    return frames, k, how, b"".join(encoded)


@SETTINGS
@given(damaged_streams(), cuts)
def test_a_damaged_frame_is_never_taken_for_another_and_the_good_ones_around_it_are_all_found(case, at):
    frames, k, how, stream = case
    dec = F.Decoder()
    got = decode(dec, split(stream, at))
    expected = frames[:k] + frames[k + 1 :]
    assert got == expected, f"{how} in frame {k} of {frames}: expected the others {expected}, got {got}"
    c = dec.counters()
    noticed = c["bad_crc"] + c["bad_length"] + c["truncated"] + c["skipped_bytes"]
    assert noticed >= 1, f"{how} in frame {k}: expected the damage counted, counters {c}"
    gap = 1 if 0 < k < len(frames) - 1 else 0  # the lost frame between two good ones
    assert c["seq_gaps"] == gap, f"{how} in frame {k} of {len(frames)}: expected {gap} sequence gap, counters {c}"


@SETTINGS
@given(good_frames(1, 6), st.lists(garbage, min_size=7, max_size=7), cuts)
def test_good_frames_surrounded_by_garbage_are_all_found(frames, junk, at):
    stream = junk[0] + b"".join(F.encode(*f) + g for f, g in zip(frames, junk[1:]))
    dec = F.Decoder()
    got = decode(dec, split(stream, at))
    assert got == frames, f"expected {frames} among garbage {junk}, got {got}"
    assert dec.counters()["seq_gaps"] == 0 and dec.counters()["frames"] == len(frames), dec.counters()


def test_false_starts_claiming_one_length_share_their_crc_work_and_take_the_same_frames():
    """Start bytes claiming 4096-byte frames, good frames in their midst and after, one
    of them 4096 bytes long: the decoder shares the CRC work of the false starts (its
    cheap resync) and takes exactly what the reference takes, whole or in 7-byte reads."""
    head = adversarial_header(F.MAX_PAYLOAD)
    good = [(F.OUT, 1, b"x" * 30), (F.UART_TX, 2, b"y" * F.MAX_PAYLOAD), (F.WAIT, 3, b"z" * 300)]
    stream = head * 1000 + F.encode(*good[0]) + head * 1000 + F.encode(*good[1]) + F.encode(*good[2])
    for pieces in ([stream], split(stream, list(range(0, len(stream), 7)))):
        dec, ref = F.Decoder(), ReferenceDecoder()
        dec.share_after = 16  # (MicroPython's default; CPython's is None)
        got = decode(dec, pieces)
        assert dec._shared is not None, "expected the false starts' CRC work shared"
        assert got == decode(ref, pieces) == good, got
        assert dec.counters() == ref.counters(), (dec.counters(), ref.counters())
