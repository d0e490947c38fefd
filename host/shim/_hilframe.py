# Frame codec of the plant link. One file for both ends: MicroPython imports it in the
# shim, CPython imports it as host.shim._hilframe. Byte layout: docs/protocol.md.
import struct
import sys

try:
    from binascii import crc32
except ImportError:  # a board build without binascii.crc32

    def crc32(data, crc=0):
        crc ^= 0xFFFFFFFF
        for b in data:
            crc ^= b
            for _ in range(8):
                crc = (crc >> 1) ^ (0xEDB88320 & -(crc & 1))
        return crc ^ 0xFFFFFFFF


PROTO_VERSION = 7  # 3: POLL, CFG's instant; 4: BUS_IMAGE, BUS_DONE; 5: BUS_IMAGE read in place, EDGES, I2CT, CPU_RUNS;
# 6: the shim's settings in WELCOME; 7: BUS_IMAGE entries' windows and streams
SOF = 0xA5
HEADER_LEN = 5  # SOF, type, seq, length (u16)
CRC_LEN = 4
MAX_PAYLOAD = 4096
_SOF_BYTES = b"\xa5"
_F32 = 0xFFFFFFFF
_LONG = 252  # a payload this long has its CRC taken through a memoryview, not over a copy
# false starts claiming one length before their CRC work is shared (Decoder.share_after);
# CPython's crc32 (zlib) outruns the sharing
_SHARE_AFTER = 16 if sys.implementation.name == "micropython" else None


def encode(type_, seq, payload):
    """One frame: SOF | type | seq | len | payload | CRC-32 of type..payload."""
    n = len(payload)
    if n > MAX_PAYLOAD:
        raise ValueError("payload of %d bytes exceeds %d" % (n, MAX_PAYLOAD))
    head = struct.pack("<BBH", type_, seq & 0xFF, n)
    crc = crc32(payload, crc32(head)) & 0xFFFFFFFF
    return _SOF_BYTES + head + payload + struct.pack("<I", crc)


def _advance(reg, data):
    """The CRC-32 register after ``data``, from ``reg`` (no inversion in or out)."""
    return ~crc32(data, ~reg & _F32) & _F32


def _words(values):
    try:
        from array import array

        return array("I", values)  # 4 bytes a word, not boxed ints on a 32-bit board
    except ImportError:
        return values


def _zeros_map(m):
    """The register advanced over ``m`` zero bytes, a linear map, as four 256-entry
    tables (one per byte of the register): 1024 words, built with 32 CRCs of m bytes;
    then the register's byte-by-byte update table (256 words)."""
    zeros = bytes(m)
    table = [0] * 1280
    for j in range(4):
        for k in range(8):
            image = _advance(1 << (8 * j + k), zeros)
            step = 1 << k
            for b in range(step, 2 * step):
                table[256 * j + b] = table[256 * j + b - step] ^ image
    for b in range(256):
        table[1024 + b] = _advance(b, b"\0")
    return _words(table)


def _carry(reg, buf, view, k, stop, t):
    """The register carried over buf[k:stop]: byte by byte (no allocation) over a few
    bytes, with the C crc32 over more."""
    if stop - k > 24:
        return _advance(reg, view[k:stop])
    while k < stop:
        reg = t[1024 + ((reg ^ buf[k]) & 255)] ^ (reg >> 8)
        k += 1
    return reg


class Decoder:
    """Incremental decoder: feed() bytes, then pop frames with next().

    A frame with a bad length or a bad CRC is dropped and counted, and decoding
    resumes at the next SOF after its first byte. expire() drops a partial frame
    that stopped arriving (counted as truncated). Sequence numbers are checked per
    direction; a gap is counted (a frame was lost) but the good frame is kept; a frame
    with the sequence number of the one before it is the same frame again: dropped and
    counted as a duplicate. ``damaged`` counts every loss (bad length, bad CRC,
    truncation, gap) in one number the ends check after each frame.

    Cost (docs/reliability.md): fed bytes are kept as they come while frames are taken
    whole; a partial frame grows in a bytearray, moved only once most of it has been
    taken, so each byte is copied a bounded number of times however small the reads.
    The length and the CRC field are read by index and a long body's CRC is taken
    through a memoryview: a false start (an SOF in noise or in a damaged frame) costs
    one C crc32 over at most the length it claims, with no copy. When false starts keep
    claiming one length (start bytes claiming 4 KiB frames, over and over), their checks
    share the CRC work: the register is carried along the buffer at the starts and at
    the ends of the claimed frames, and the CRC of each claimed frame follows from the
    two with a 5 KiB table of the register advanced over that many zero bytes (CRC-32
    is affine: crc(a + b) = crc(a) advanced over len(b) zeros, xor crc(b) from zero),
    with no allocation per false start (on MicroPython an allocation can cost more than
    the rest, the heap being searched for room). On by default on MicroPython only:
    CPython's crc32 (zlib) runs through 4 KiB faster than the sharing's Python does.
    Exactly the same frames are accepted either way (host/tests/test_codec_properties.py).
    """

    def __init__(self):
        self.buf = b""  # bytes, or a bytearray while a partial frame grows
        self._grown = False  # (the buffer is that bytearray: payloads are copied out as bytes)
        self.pos = 0
        self.frames = 0
        self.bad_crc = 0
        self.bad_length = 0
        self.truncated = 0
        self.skipped = 0
        self.seq_gaps = 0
        self.duplicates = 0
        self.duplicate_bytes = 0
        self.damaged = 0
        self.expect_seq = -1
        self.on_skip = None  # called with bytes found outside frames (a board's console text)
        self.share_after = _SHARE_AFTER  # None: every false start pays its own CRC
        self._run = [-1, 0]  # the length the last false starts claimed, how many in a row
        self._shared = None  # [length, table, start, register there, end, register there]

    def feed(self, data):
        buf = self.buf
        pos = self.pos
        if pos >= len(buf):  # everything before was taken (the usual case): no copy
            buf = bytes(data)
            self._grown = False
        elif pos * 2 >= len(buf):  # the rest is no longer than what was taken: move it once
            buf = bytearray(memoryview(buf)[pos:])
            buf += data
            self._grown = True
        else:
            if not isinstance(buf, bytearray):
                buf = bytearray(buf)
                self._grown = True
            buf += data  # in place: a long frame fed in small reads is not copied again
            self.buf = buf
            return
        self.buf = buf
        self.pos = 0
        if self._shared is not None:
            self._shared[2] = self._shared[4] = -1  # the offsets moved: carry the registers anew

    def pending(self):
        return len(self.buf) - self.pos

    def next(self):
        """The next good frame as (type, seq, payload), or None if none is complete."""
        buf = self.buf
        size = len(buf)
        pos = self.pos
        view = None
        while True:
            i = buf.find(_SOF_BYTES, pos)
            if i < 0:
                i = size
            if i > pos:
                self.skipped += i - pos
                if self.on_skip is not None:
                    self.on_skip(bytes(buf[pos:i]))
            if i + HEADER_LEN > size:
                self.pos = i
                return None
            n = buf[i + 3] | buf[i + 4] << 8
            if n > MAX_PAYLOAD:
                self.bad_length += 1
                self.damaged += 1
                pos = i + 1
                continue
            end = i + HEADER_LEN + n
            if end + CRC_LEN > size:
                self.pos = i
                return None
            if n < _LONG:  # (the usual frame) the CRC over a copy of type..payload
                ok = crc32(buf[i + 1 : end]) == struct.unpack_from("<I", buf, end)[0]  # (crc32 is unsigned)
            else:
                if view is None:
                    view = memoryview(buf)
                ok = self._crc_ok(buf, view, i + 1, end)
            if not ok:
                self.bad_crc += 1
                self.damaged += 1
                pos = i + 1
                continue
            seq = buf[i + 2]
            if self.expect_seq >= 0 and seq == (self.expect_seq - 1) & 0xFF:  # the last frame again
                self.pos = pos = end + CRC_LEN
                self.duplicates += 1
                self.duplicate_bytes += end + CRC_LEN - i
                continue
            # the payload copied before the decoder moves on: a MemoryError here leaves the
            # frame to be taken again (the shim's reserve, host/shim/_hil.py)
            payload = bytes(buf[i + HEADER_LEN : end]) if self._grown else buf[i + HEADER_LEN : end]
            self.pos = end + CRC_LEN
            if self.expect_seq >= 0 and seq != self.expect_seq:
                self.seq_gaps += 1
                self.damaged += 1
            self.frames += 1
            self.expect_seq = (seq + 1) & 0xFF
            return buf[i + 1], seq, payload

    def _crc_ok(self, buf, view, start, end):
        """Whether the four bytes at ``end`` are the CRC-32 of buf[start:end], a long body."""
        want = buf[end] | buf[end + 1] << 8 | buf[end + 2] << 16 | buf[end + 3] << 24
        m = end - start
        shared = self._shared
        if shared is not None and shared[0] == m and shared[2] <= start and shared[4] <= end:
            if shared[2] < 0:
                shared[2] = shared[4] = start
                shared[3] = shared[5] = 0
            t = shared[1]
            reg_start = shared[3] = _carry(shared[3], buf, view, shared[2], start, t)
            reg_end = shared[5] = _carry(shared[5], buf, view, shared[4], end, t)
            shared[2] = start
            shared[4] = end
            r = reg_start ^ _F32
            return reg_end ^ t[r & 255] ^ t[256 + (r >> 8 & 255)] ^ t[512 + (r >> 16 & 255)] ^ t[768 + (r >> 24)] == (
                want ^ _F32
            )
        if crc32(view[start:end]) & _F32 == want:
            return True
        run = self._run
        if run[0] == m:
            run[1] += 1
            if run[1] == self.share_after:
                self._shared = [m, _zeros_map(m), -1, 0, -1, 0]
        else:
            run[0] = m
            run[1] = 1
        return False

    def expire(self):
        """Drop a partial frame whose rest never came; True if one was dropped."""
        if self.pending() == 0:
            return False
        self.truncated += 1
        self.damaged += 1
        self.pos += 1
        return True

    def counters(self):
        return {
            "frames": self.frames,
            "bad_crc": self.bad_crc,
            "bad_length": self.bad_length,
            "truncated": self.truncated,
            "skipped_bytes": self.skipped,
            "seq_gaps": self.seq_gaps,
            "duplicates": self.duplicates,
        }


# -- messages -----------------------------------------------------------------------
# Message types. Each payload's layout is defined once, below, as a struct format
# (little-endian) and a pack/unpack pair that both ends use; docs/protocol.md draws them.
# shim -> host
HELLO = 0x01
CFG = 0x02
OUT = 0x03
WAIT = 0x04
SEEN = 0x05
UART_TX = 0x06
FAULT = 0x07
EXIT = 0x08
BUS = 0x09  # a bus transfer (I2C, SPI): the shim waits for its BUS_REPLY
POLL = 0x0A  # a poll that never ends: one pin or memory address read with one answer (POLL_*)
CPU = 0x0B  # MCU time: the longest compute between two waits so far, with the code that ran it
CPU_IRQ = 0x0C  # MCU time: the callbacks' compute over a span (at most one a CPU_WINDOW_US)
BUS_DONE = 0x0D  # a bus read the shim answered from the last BUS_IMAGE (its entry, its instant)
CPU_RUNS = 0x10  # MCU time: the compute before each wait the shim served itself (t_us, compute_us pairs)
PIO_DONE = 0x11  # a PIO frame the shim answered from the last PIO_AHEAD (its state machine, its entry, its instant)
I2CT_DONE = 0x0F  # a controller's transaction on an I2CTarget done: what the controller read (I2CT_DONE_FMT)
EVAL_REPLY = 0x0E  # an EVAL's outcome: a value's repr, nothing, or the error's text (EVAL_*)
# host -> shim
WELCOME = 0x81
STATE = 0x82
BYE = 0x83  # (empty) the host ends the session: the firmware stops at its next wait
BUS_REPLY = 0x84  # a BUS's outcome: what the devices answered, at the BUS's instant
BUS_IMAGE = 0x85  # before a STATE or BUS_REPLY: register reads the shim may answer itself, until when
EVAL = 0x86  # while the firmware waits for a STATE: an expression or a REPL line to run in it (docs/live.md)
EDGES = 0x87  # before a STATE: encoder edges up to its t_end as segments (EDGE_SEG_FMT), which the shim expands
PIO_AHEAD = 0x88  # before a BUS_REPLY to a PIO frame: the replies to the frames the read makes next (_hilpio.py)

NAMES = {
    HELLO: "HELLO",
    CFG: "CFG",
    OUT: "OUT",
    WAIT: "WAIT",
    SEEN: "SEEN",
    UART_TX: "UART_TX",
    FAULT: "FAULT",
    EXIT: "EXIT",
    BUS: "BUS",
    POLL: "POLL",
    CPU: "CPU",
    CPU_IRQ: "CPU_IRQ",
    BUS_DONE: "BUS_DONE",
    EVAL_REPLY: "EVAL_REPLY",
    I2CT_DONE: "I2CT_DONE",
    CPU_RUNS: "CPU_RUNS",
    PIO_DONE: "PIO_DONE",
    WELCOME: "WELCOME",
    STATE: "STATE",
    BYE: "BYE",
    BUS_REPLY: "BUS_REPLY",
    BUS_IMAGE: "BUS_IMAGE",
    EVAL: "EVAL",
    EDGES: "EDGES",
    PIO_AHEAD: "PIO_AHEAD",
}

HELLO_FMT = "<H"  # proto, then UTF-8 "<micropython version>;<machine>"
WELCOME_FMT = "<HBQB"  # proto, mode, t_start_us, flags, then the settings: WELCOME_SETTINGS_FMT, WELCOME_TEXTS
WELCOME_LEN = struct.calcsize(WELCOME_FMT)
WELCOME_SETTINGS_FMT = "<IIIII"  # the numbers of WELCOME_NUMBERS, in order
WELCOME_SETTINGS_LEN = struct.calcsize(WELCOME_SETTINGS_FMT)
# The shim's settings (docs/protocol.md, "Settings"): numbers, then byte strings (each a u16
# length and its bytes). The host writes each one's default once (host/rig/targets/firmware.py).
WELCOME_NUMBERS = ("console_baud", "ticks_wrap_ms", "flash_bytes", "heap_bytes", "cpu_heap")
WELCOME_TEXTS = ("identity", "entry", "board_fs", "allow", "cpu", "cpu_cost")
WELCOME_ZERO_DELAY = 0x01  # flag: a wire may carry an output to an input at the same instant
CFG_FMT = "<QHBBBi"  # t_us, handle, kind, mode, pull, param, then UTF-8 pin name
OUT_FMT = "<QHBi"  # t_us, handle, attr, value
WAIT_FMT = "<QQI"  # t_now_us, t_until_us, compute_us, then WATCH_FMT per watched handle
WATCH_FMT = "<H"
SEEN_FMT = "<QHI"  # t_us, handle, sample number
UART_TX_FMT = "<QH"  # t_us, handle, then the bytes
FAULT_FMT = "<Q"  # t_us, then UTF-8 traceback
EXIT_FMT = "<QBi"  # t_us, kind, code
STATE_FMT = "<QQQH"  # base_us, t_end_us, horizon_us, count, then count changes:
CHANGE_FMT = "<IHBiI"  # dt_us (from base), handle, kind, value, extra (+ value bytes for CH_BYTES)
BUS_FMT = "<QHBHH"  # t_us, handle, op, address, read count, then the bytes written
BUS_IMAGE_FMT = "<QHQ"  # t_us (the plant's), entries, horizon_us, then each: BUS_IMAGE_ENTRY_FMT, written, read
# handle, address, bytes written, bytes read, from and until (exclusive) in us after the image's
# t_us, its stream (0: none), the stream's count it needs and the count it leaves
BUS_IMAGE_ENTRY_FMT = "<HHBBIIBBB"
BUS_DONE_FMT = "<QH"  # t_us (the read's instant), the image's entry (its offset in the payload)
BUS_REPLY_FMT = "<QBHQ"  # t_us (the BUS's), status, count (acks), horizon_us, then the bytes read
I2CT_DONE_FMT = "<QHBH"  # t_us, the target's handle, status (BUS_*), acks, then the bytes the controller read
EDGES_FMT = "<QH"  # base_us (the STATE's), segments, then each EDGE_SEG_FMT:
EDGE_SEG_FMT = "<HHBBBQqIQdd"  # handle of channel a, of b (NO_HANDLE: none), mask, a's and b's level by
# count & mask (bit k), first edge's t_us, count before it, edges, then t0_us, p0, rate of the edge
# times after the first: count m reached at t0 + ceil((m - p0) / rate) (rate > 0), t0 + ceil((p0 - (m + 1)) / -rate)
EVAL_FMT = "<B"  # EVAL_EXPR or EVAL_LINE, then the UTF-8 source
EVAL_REPLY_FMT = "<B"  # EVAL_VALUE, EVAL_NONE or EVAL_ERROR, then UTF-8 text (the repr, the error)
POLL_FMT = "<QQIBBII"  # t_us, since_us, reads, kind, bits, target, value; then UTF-8 lines: the
# shim's word on what would change it, then the firmware's stack (innermost last) when known

HELLO_LEN = struct.calcsize(HELLO_FMT)
CFG_LEN = struct.calcsize(CFG_FMT)
WAIT_LEN = struct.calcsize(WAIT_FMT)
WATCH_LEN = struct.calcsize(WATCH_FMT)
UART_TX_LEN = struct.calcsize(UART_TX_FMT)
FAULT_LEN = struct.calcsize(FAULT_FMT)
STATE_LEN = struct.calcsize(STATE_FMT)
EDGES_LEN = struct.calcsize(EDGES_FMT)
EDGE_SEG_LEN = struct.calcsize(EDGE_SEG_FMT)
NO_HANDLE = 0xFFFF  # an encoder channel of an EDGES segment wired to no pin
CHANGE_LEN = struct.calcsize(CHANGE_FMT)
BUS_LEN = struct.calcsize(BUS_FMT)
BUS_REPLY_LEN = struct.calcsize(BUS_REPLY_FMT)
BUS_IMAGE_LEN = struct.calcsize(BUS_IMAGE_FMT)
BUS_IMAGE_ENTRY_LEN = struct.calcsize(BUS_IMAGE_ENTRY_FMT)
POLL_LEN = struct.calcsize(POLL_FMT)
CPU_FMT = "<QII"  # t_us (the wait it ends at), compute_us, its largest charge's µs; then UTF-8 stack lines
CPU_LEN = struct.calcsize(CPU_FMT)
CPU_IRQ_FMT = "<QQI"  # t_from_us, t_us, the callbacks' compute_us between them
CPU_RUNS_FMT = "<H"  # runs, then each CPU_RUN_FMT: the wait's instant (its start), the compute before it
CPU_RUN_FMT = "<QI"
CPU_RUNS_MAX = 32  # runs a CPU_RUNS message holds at most (the shim sends one when it has that many)
CPU_WINDOW_US = 100_000  # the CPU load's window (host/rig/targets/mcutime.py)


def pack_hello(info):
    return struct.pack(HELLO_FMT, PROTO_VERSION) + info


def unpack_hello(p):
    """(proto, info bytes)"""
    return struct.unpack_from(HELLO_FMT, p, 0)[0], bytes(p[HELLO_LEN:])


def pack_welcome(mode, t_start_us, flags, settings):
    """``settings``: a dict of every name of WELCOME_NUMBERS (an int) and WELCOME_TEXTS (bytes)."""
    out = struct.pack(WELCOME_FMT, PROTO_VERSION, mode, t_start_us, flags)
    out += struct.pack(WELCOME_SETTINGS_FMT, *[settings[name] for name in WELCOME_NUMBERS])
    for name in WELCOME_TEXTS:
        out += struct.pack("<H", len(settings[name])) + settings[name]
    return out


def unpack_welcome(p):
    """(proto, mode, t_start_us, flags, settings: a dict as pack_welcome takes it; its
    identity b"<platform>;<machine>" or b"")"""
    settings = dict(zip(WELCOME_NUMBERS, struct.unpack_from(WELCOME_SETTINGS_FMT, p, WELCOME_LEN)))
    at = WELCOME_LEN + WELCOME_SETTINGS_LEN
    for name in WELCOME_TEXTS:
        end = at + 2 + struct.unpack_from("<H", p, at)[0]
        settings[name] = bytes(p[at + 2 : end])
        at = end
    return struct.unpack_from(WELCOME_FMT, p, 0) + (settings,)


def pack_cfg(t_us, handle, kind, mode, pull, param, name):
    return struct.pack(CFG_FMT, t_us, handle, kind, mode, pull, param) + name


def unpack_cfg(p):
    """(t_us, handle, kind, mode, pull, param, name bytes)"""
    return struct.unpack_from(CFG_FMT, p, 0) + (bytes(p[CFG_LEN:]),)


def pack_out(t_us, handle, attr, value):
    return struct.pack(OUT_FMT, t_us, handle, attr, value)


def unpack_out(p):
    """(t_us, handle, attr, value)"""
    return struct.unpack_from(OUT_FMT, p, 0)


def pack_wait(t_now_us, t_until_us, compute_us, watch=()):
    payload = struct.pack(WAIT_FMT, t_now_us, t_until_us, compute_us)
    for h in watch:
        payload += struct.pack(WATCH_FMT, h)
    return payload


def unpack_wait(p):
    """(t_now_us, t_until_us, compute_us, watched handles as a tuple)"""
    fixed = struct.unpack_from(WAIT_FMT, p, 0)
    n = (len(p) - WAIT_LEN) // WATCH_LEN
    if n <= 0:
        return fixed + ((),)
    return fixed + (struct.unpack_from("<%d%s" % (n, WATCH_FMT[1:]), p, WAIT_LEN),)


def pack_seen(t_us, handle, sample_no):
    return struct.pack(SEEN_FMT, t_us, handle, sample_no)


def unpack_seen(p):
    """(t_us, handle, sample number)"""
    return struct.unpack_from(SEEN_FMT, p, 0)


def pack_uart_tx(t_us, handle, data):
    return struct.pack(UART_TX_FMT, t_us, handle) + data


def unpack_uart_tx(p):
    """(t_us, handle, bytes)"""
    return struct.unpack_from(UART_TX_FMT, p, 0) + (bytes(p[UART_TX_LEN:]),)


def pack_fault(t_us, text):
    """A traceback too long for one frame keeps its end (the exception's type and text)."""
    room = MAX_PAYLOAD - FAULT_LEN
    if len(text) > room:
        text = text[len(text) - room :]
    return struct.pack(FAULT_FMT, t_us) + text


def unpack_fault(p):
    """(t_us, traceback bytes)"""
    return struct.unpack_from(FAULT_FMT, p, 0)[0], bytes(p[FAULT_LEN:])


def pack_exit(t_us, kind, code):
    return struct.pack(EXIT_FMT, t_us, kind, code)


def unpack_exit(p):
    """(t_us, kind, code)"""
    return struct.unpack_from(EXIT_FMT, p, 0)


def pack_bus(t_us, handle, op, address, n_read, data):
    return struct.pack(BUS_FMT, t_us, handle, op, address, n_read) + data


def unpack_bus(p):
    """(t_us, handle, op, address, read count, bytes written)"""
    return struct.unpack_from(BUS_FMT, p, 0) + (bytes(p[BUS_LEN:]),)


def pack_bus_reply(t_us, status, count, horizon_us, data):
    return struct.pack(BUS_REPLY_FMT, t_us, status, count, horizon_us) + data


def pack_bus_image(t_us, horizon_us, entries):
    """entries: (handle, address, from_us, until_us, stream, need, then, bytes written, bytes
    read) each; from_us and until_us after ``t_us``."""
    return struct.pack(BUS_IMAGE_FMT, t_us, len(entries), horizon_us) + b"".join(
        struct.pack(BUS_IMAGE_ENTRY_FMT, h, address, len(wrote), len(got), from_us, until_us, stream, need, then)
        + wrote
        + got
        for h, address, from_us, until_us, stream, need, then, wrote, got in entries
    )


def unpack_bus_image(p):
    """(t_us, horizon_us, [(handle, address, from_us, until_us, stream, need, then, bytes
    written, bytes read)])."""
    t_us, n, horizon_us = struct.unpack_from(BUS_IMAGE_FMT, p, 0)
    off = BUS_IMAGE_LEN
    entries = []
    for _ in range(n):
        handle, address, n_wrote, n_read, from_us, until_us, stream, need, then = struct.unpack_from(
            BUS_IMAGE_ENTRY_FMT, p, off
        )
        off += BUS_IMAGE_ENTRY_LEN
        wrote, off = bytes(p[off : off + n_wrote]), off + n_wrote
        entries.append((handle, address, from_us, until_us, stream, need, then, wrote, bytes(p[off : off + n_read])))
        off += n_read
    return t_us, horizon_us, entries


def bus_image_find(p, handle, address, wrote, n_read, t_us, streams):
    """Where the BUS_IMAGE payload ``p`` (bytes) has the entry for a register read (``wrote``:
    bytes) at ``t_us``: its offset in ``p``, or -1. An entry answers inside its window and,
    if it is one of a stream's (a chip's samples and status bits, read in turn), only while
    ``streams`` (a bytearray: each stream's count of reads answered, zeros with each new
    image) holds the count it needs; ``bus_image_took`` then moves the count on. The shim's
    lookup at each transfer: the payload is kept as it came and read in place a byte at a
    time, allocating nothing (nothing decoded at a STATE; the instants built from their
    bytes, small ints); ``bus_image_got`` reads the bytes."""
    off = BUS_IMAGE_LEN
    end = len(p)
    n_wrote = len(wrote)
    dt = -1
    while off < end:
        nw = p[off + 4]
        if (
            p[off + 2] == address & 0xFF
            and p[off + 5] == n_read
            and nw == n_wrote
            and p[off] | p[off + 1] << 8 == handle
            and p[off + 3] == address >> 8
        ):
            stream = p[off + 14]
            if not stream or streams[stream] == p[off + 15]:  # (a stream's past windows end here)
                start = off + BUS_IMAGE_ENTRY_LEN
                if (p[start] == wrote[0]) if nw == 1 else (p[start : start + nw] == wrote):
                    if dt < 0:  # (the instant after the image's, once)
                        t0 = p[0] | p[1] << 8 | p[2] << 16 | p[3] << 24
                        dt = t_us - (t0 | (p[4] | p[5] << 8 | p[6] << 16 | p[7] << 24) << 32)
                    if p[off + 6] | p[off + 7] << 8 | p[off + 8] << 16 | p[off + 9] << 24 <= dt:
                        if dt < p[off + 10] | p[off + 11] << 8 | p[off + 12] << 16 | p[off + 13] << 24:
                            return off
        off += BUS_IMAGE_ENTRY_LEN + nw + p[off + 5]
    return -1


def bus_image_took(p, off, streams):
    """The entry at ``off`` answered a read: its stream's count moves on."""
    stream = p[off + 14]
    if stream:
        streams[stream] = p[off + 16]


def bus_image_got(p, off):
    """The bytes the entry at ``off`` of the BUS_IMAGE payload ``p`` reads."""
    start = off + BUS_IMAGE_ENTRY_LEN + p[off + 4]
    return p[start : start + p[off + 5]]


def bus_image_offsets(entries):
    """The offset of each entry (as ``pack_bus_image`` takes them) in the payload it makes of
    them: the entry BUS_DONE names."""
    offsets, off = [], BUS_IMAGE_LEN
    for entry in entries:
        offsets.append(off)
        off += BUS_IMAGE_ENTRY_LEN + len(entry[7]) + len(entry[8])
    return offsets


def bus_image_horizon(p):
    """The horizon a read answered from the BUS_IMAGE payload ``p`` leaves the shim."""
    return struct.unpack_from("<Q", p, 10)[0]


def pack_bus_done(t_us, entry):
    return struct.pack(BUS_DONE_FMT, t_us, entry)


def unpack_cpu_runs(p):
    """[(t_us, compute_us), ...]"""
    (n,) = struct.unpack_from(CPU_RUNS_FMT, p, 0)
    size, run = struct.calcsize(CPU_RUNS_FMT), struct.calcsize(CPU_RUN_FMT)
    return [struct.unpack_from(CPU_RUN_FMT, p, size + i * run) for i in range(n)]


def unpack_i2ct_done(p):
    """(t_us, handle, status, acks, the bytes the controller read)"""
    t, h, status, acks = struct.unpack_from(I2CT_DONE_FMT, p, 0)
    return t, h, status, acks, bytes(p[struct.calcsize(I2CT_DONE_FMT) :])


def unpack_bus_done(p):
    return struct.unpack_from(BUS_DONE_FMT, p, 0)


def unpack_bus_reply(p):
    """(t_us, status, count, horizon_us, bytes read)"""
    return struct.unpack_from(BUS_REPLY_FMT, p, 0) + (bytes(p[BUS_REPLY_LEN:]),)


def pack_eval(mode, source):
    return struct.pack(EVAL_FMT, mode) + source


def unpack_eval(p):
    """(mode, source bytes)"""
    return p[0], bytes(p[1:])


def pack_eval_reply(status, text):
    """A text too long for one frame keeps its start (a repr) and says it was cut."""
    if len(text) > MAX_PAYLOAD - 1:
        text = text[: MAX_PAYLOAD - 4] + b"..."
    return struct.pack(EVAL_REPLY_FMT, status) + text


def unpack_eval_reply(p):
    """(status, text bytes)"""
    return p[0], bytes(p[1:])


def pack_poll(t_us, since_us, reads, kind, bits, target, value, text):
    return struct.pack(POLL_FMT, t_us, since_us, reads, kind, bits, target, value) + text


def unpack_poll(p):
    """(t_us, since_us, reads, kind, bits, target, value, text bytes)"""
    return struct.unpack_from(POLL_FMT, p, 0) + (bytes(p[POLL_LEN:]),)


def pack_state(base_us, t_end_us, horizon_us, changes):
    """changes: (t_us, handle, kind, value, extra) in time order; for CH_BYTES, value is
    the byte count and extra the bytes. Times before base_us are sent as base_us."""
    flat = []
    add = flat.extend
    for t, h, kind, value, extra in changes:
        if kind == CH_BYTES:
            return _pack_state_bytes(base_us, t_end_us, horizon_us, changes)
        add((t - base_us if t > base_us else 0, h, kind, value, extra))
    n = len(changes)
    return struct.pack(STATE_FMT + CHANGE_FMT[1:] * n, base_us, t_end_us, horizon_us, n, *flat)


def _pack_state_bytes(base_us, t_end_us, horizon_us, changes):
    """pack_state with UART bytes among the changes: a part at a time."""
    parts = [struct.pack(STATE_FMT, base_us, t_end_us, horizon_us, len(changes))]
    for t, h, kind, value, extra in changes:
        dt = t - base_us if t > base_us else 0
        if kind == CH_BYTES:
            parts.append(struct.pack(CHANGE_FMT, dt, h, kind, value, 0) + extra)
        else:
            parts.append(struct.pack(CHANGE_FMT, dt, h, kind, value, extra))
    return b"".join(parts)


def unpack_state(p):
    """(base_us, t_end_us, horizon_us, changes as (t_us, handle, kind, value, extra))"""
    base, t_end, horizon, n = struct.unpack_from(STATE_FMT, p, 0)
    return base, t_end, horizon, unpack_changes(p, STATE_LEN, base, n, [])


def unpack_changes(p, off, base, n, changes):
    """``n`` of a STATE's changes from offset ``off``, appended to ``changes`` (returned)
    as (t_us, handle, kind, value, extra)."""
    for _ in range(n):
        dt, h, kind, value, extra = struct.unpack_from(CHANGE_FMT, p, off)
        off += CHANGE_LEN
        if kind == CH_BYTES:
            extra = bytes(p[off : off + value])
            off += value
        changes.append((base + dt, h, kind, value, extra))
    return changes


def pack_edges(base_us, segments):
    """An EDGES payload: segments (EDGE_SEG_FMT's fields, in the plant's encoder order)."""
    return struct.pack(EDGES_FMT, base_us, len(segments)) + b"".join(struct.pack(EDGE_SEG_FMT, *s) for s in segments)


def unpack_edges(p):
    """(base_us, [segment as EDGE_SEG_FMT's fields])"""
    base, n = struct.unpack_from(EDGES_FMT, p, 0)
    return base, [struct.unpack_from(EDGE_SEG_FMT, p, EDGES_LEN + i * EDGE_SEG_LEN) for i in range(n)]


def expand_edges(segments):
    """The segments' edges as a STATE's changes, (t_us, handle, CH_LEVEL, level, 0), in time
    order, at one instant in the segments' order: the times by the plant's own arithmetic
    (sim_plant/physics/encoder.py, _EdgeCounter.emit), IEEE double as there."""
    from math import ceil

    edges = []
    for k, (ha, hb, mask, bits_a, bits_b, t, n, count, t0, p0, rate) in enumerate(segments):
        step = 1 if rate > 0.0 else -1
        for j in range(count):
            m = n + step
            if j:
                t = t0 + (ceil((m - p0) / rate) if step > 0 else ceil((p0 - (m + 1)) / -rate))
            a, a_was = bits_a >> (m & mask) & 1, bits_a >> (n & mask) & 1
            if a != a_was:
                if ha != NO_HANDLE:
                    edges.append((t, k, ha, a))
            elif hb != NO_HANDLE:
                edges.append((t, k, hb, bits_b >> (m & mask) & 1))
            n = m
    edges.sort()  # (by time, then segment: no two edges of one segment share an instant)
    return [(t, h, CH_LEVEL, level, 0) for t, _k, h, level in edges]


def merge_edges(segments, changes):
    """The changes a STATE and its EDGES give the firmware, in the order it takes them: the
    segments' edges (``expand_edges``) and the STATE's changes in time order, at one instant
    the edges first (the plant emits an instant's encoder edges before its other parts'
    changes). The shim's pure path applies these (``_hil._apply_state``; ``_hilfast.merge_edges``
    the same in C); the host's trace records them."""
    merged = expand_edges(segments)
    i = 0
    for c in changes:  # (stable: the edges of an instant before its changes)
        while i < len(merged) and merged[i][0] <= c[0]:
            i += 1
        merged.insert(i, c)
        i += 1
    return merged


# CFG kinds: one per shim class with a host side (machine.Pin, ADC, PWM, UART; an IRQ
# arms a pin or a UART already configured). The host's handler of each: host/rig/hardware/peripherals.py.
CFG_PIN = 1
CFG_ADC = 2
CFG_PWM = 3
CFG_UART = 4
CFG_IRQ = 5
CFG_I2C = 6  # machine.I2C / SoftI2C: name "i2c<id>" or "i2c:<scl>,<sda>"; param the clock (Hz)
CFG_SPI = 7  # machine.SPI / SoftSPI: name "spi<id>" or "spi:<sck>,<mosi>,<miso>"; param the baud rate
CFG_I2CT = 8  # machine.I2CTarget: name "i2ct<id>"; param its address (-1: deinit); transactions are CH_BYTES (I2CT_*)
CFG_PIO = 16  # rp2.StateMachine: name "sm<id>" (0..7; 4..7 are PIO1's); its ops are BUS_PIO_* frames

# BUS ops. I2C: XFER is [start, address+W, the bytes written][(re)start, address+R, read
# count bytes][stop]: no bytes written and none read is a probe (scan's). XFER_NOSTOP
# leaves the bus held. The SoftI2C primitives: START, WRITE (the first byte after a start
# is the address byte), READ (NACK its last byte; READ_ACK: ACK it), STOP. SPI: SPI_XFER
# clocks the bytes written out, as many in (the devices whose chip select is low).
BUS_XFER = 0
BUS_XFER_NOSTOP = 1
BUS_START = 2
BUS_WRITE = 3
BUS_READ = 4
BUS_READ_ACK = 5
BUS_STOP = 6
BUS_SPI_XFER = 7
BUS_SCAN = 8  # every address 0x08..0x77 probed: the bytes read are those that acknowledged
BUS_BITSTREAM = 9  # machine.bitstream on a pin's handle: data = the timing (4 x <I, ns), then the bytes
# BUS ops on a state machine's handle (rp2, docs/shim.md "PIO"; the host runs the PIO: sim_plant/pio).
# INIT: data = <IIIII execctrl shiftctrl pinctrl freq_hz pc>, the PIO's 32 words <32H>, then
# <BBB gpio, is_output, level> per pin the program's *_init sets. PUT: data = <I words; GET: read
# count words. PUT and GET reply <I wait_us> (how long until it may go on with the pins as they
# are, 0: never) before the words taken (count) or read. LEVELS replies <BB rx, tx>, then the RX
# words (the shim takes gets at that instant from them). EXEC: <H word>. Every op's address
# carries, above its low byte, the RX words the firmware took since (at the last frame's instant).
BUS_PIO_INIT = 16
BUS_PIO_ACTIVE = 17  # address: 1 run, 0 stop
BUS_PIO_PUT = 18
BUS_PIO_GET = 19
BUS_PIO_LEVELS = 20
BUS_PIO_EXEC = 21
BUS_PIO_RESTART = 22
BUS_PIO_IRQ = 23  # address: the block's flags 0..3 with a handler; reply: count raises, <I t_us> each, then their flags
# BUS_REPLY statuses: the shim turns each into its board's OSError (ENODEV, EIO, ETIMEDOUT)
BUS_OK = 0
BUS_ASK_STACK = 0x80  # in a BUS_REPLY's status: the host names a poll of this read and asks the
# shim for the firmware's stack (a POLL of kind POLL_STACK, at once); the rest is the status
BUS_NACK_ADDRESS = 1  # nobody acknowledged the address byte
BUS_NACK_DATA = 2  # a written byte was not acknowledged (count: the acks before it)
BUS_STUCK = 3  # a device holds the bus: the transfer times out

# CFG_PIN's mode and pull fields
PIN_IN = 0
PIN_OUT = 1
PIN_OPEN_DRAIN = 2
PIN_ALT = 3  # rp2: the pin handed to a peripheral function (param: its GPIO_FUNC_*); SIO drives it no more
PULL_NONE = 0
PULL_UP = 1
PULL_DOWN = 2
# CFG_IRQ's mode field: the edges whose handler runs (the ESP32 port's Pin.IRQ_* values);
# for a UART, IRQ_RX: its handler runs as bytes arrive
IRQ_RISING = 1
IRQ_FALLING = 2
IRQ_RX = 1

# OUT attributes
OUT_LEVEL = 0
OUT_DUTY = 1
OUT_FREQ = 2
OUT_DEINIT = 3

# STATE change kinds
CH_LEVEL = 0
CH_SAMPLE = 1  # extra: the sample number
CH_BYTES = 2  # value: the byte count; the bytes follow the entry
# an I2CTarget's CH_BYTES: the controller's BUS op (XFER, XFER_NOSTOP), read count, then the bytes written
I2CT_XACT_FMT = "<BH"

# POLL kinds (its target): a pin read through Pin.value() (the pin's handle), machine.mem8/16/32
# at an address no register of the board's model lies behind (the address), or at one of its
# registers (the address). A poll is named once POLL_READS reads in a row with one answer span
# POLL_SPAN_US of virtual time (docs/reliability.md, "A poll that never ends").
POLL_PIN = 0
POLL_MEM = 1
POLL_REG = 2
POLL_STACK = 3  # not a poll: the firmware's stack for a bus poll the host named (BUS_ASK_STACK)
POLL_SPIN = 4  # a loop of the firmware's own code that called nothing of the board's (_hil._branches; target
# 0; value 1: named, with the stack; 0: the host only hears that the board is alive)
POLL_READS = 10_000
POLL_SPAN_US = 1_000_000

# EVAL's mode and EVAL_REPLY's status
EVAL_EXPR = 0  # an expression, in the firmware's globals and its loaded modules: its repr back
EVAL_LINE = 1  # a REPL line in the firmware's globals: an expression's repr back, or nothing
EVAL_VALUE = 0
EVAL_NONE = 1
EVAL_ERROR = 2

EXIT_RETURN = 0
EXIT_RESET = 1
EXIT_SYSEXIT = 2

MODE_LOCKSTEP = 0
MODE_REALTIME = 1

FOREVER_US = 0xFFFFFFFFFFFFFFFF
