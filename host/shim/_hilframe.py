# Frame codec of the plant link. One file for both ends: MicroPython imports it in the
# shim, CPython imports it as host.shim._hilframe. Byte layout: docs/protocol.md.
import struct

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

PROTO_VERSION = 1
SOF = 0xA5
HEADER_LEN = 5  # SOF, type, seq, length (u16)
CRC_LEN = 4
MAX_PAYLOAD = 4096
_SOF_BYTES = b"\xa5"


def encode(type_, seq, payload):
    """One frame: SOF | type | seq | len | payload | CRC-32 of type..payload."""
    n = len(payload)
    if n > MAX_PAYLOAD:
        raise ValueError("payload of %d bytes exceeds %d" % (n, MAX_PAYLOAD))
    head = struct.pack("<BBH", type_, seq & 0xFF, n)
    crc = crc32(payload, crc32(head)) & 0xFFFFFFFF
    return _SOF_BYTES + head + payload + struct.pack("<I", crc)


class Decoder:
    """Incremental decoder: feed() bytes, then pop frames with next().

    A frame with a bad length or a bad CRC is dropped and counted, and decoding
    resumes at the next SOF after its first byte. expire() drops a partial frame
    that stopped arriving (counted as truncated). Sequence numbers are checked per
    direction; a gap is counted (a frame was lost) but the good frame is kept.
    """

    def __init__(self):
        self.buf = b""
        self.pos = 0
        self.frames = 0
        self.bad_crc = 0
        self.bad_length = 0
        self.truncated = 0
        self.skipped = 0
        self.seq_gaps = 0
        self.expect_seq = -1
        self.on_skip = None  # called with bytes found outside frames (a board's console text)

    def feed(self, data):
        if self.pos:
            self.buf = self.buf[self.pos:]
            self.pos = 0
        self.buf += bytes(data)

    def pending(self):
        return len(self.buf) - self.pos

    def next(self):
        """The next good frame as (type, seq, payload), or None if none is complete."""
        buf = self.buf
        while True:
            i = buf.find(_SOF_BYTES, self.pos)
            end_skip = len(buf) if i < 0 else i
            if end_skip > self.pos:
                self.skipped += end_skip - self.pos
                if self.on_skip is not None:
                    self.on_skip(buf[self.pos:end_skip])
            if i < 0:
                self.pos = len(buf)
                return None
            self.pos = i
            if len(buf) - i < HEADER_LEN:
                return None
            type_, seq, n = struct.unpack_from("<BBH", buf, i + 1)
            if n > MAX_PAYLOAD:
                self.bad_length += 1
                self.pos = i + 1
                continue
            end = i + HEADER_LEN + n
            if len(buf) < end + CRC_LEN:
                return None
            (crc,) = struct.unpack_from("<I", buf, end)
            if crc32(buf[i + 1:end]) & 0xFFFFFFFF != crc:
                self.bad_crc += 1
                self.pos = i + 1
                continue
            self.pos = end + CRC_LEN
            self.frames += 1
            if self.expect_seq >= 0 and seq != self.expect_seq:
                self.seq_gaps += 1
            self.expect_seq = (seq + 1) & 0xFF
            return type_, seq, buf[i + HEADER_LEN:end]

    def expire(self):
        """Drop a partial frame whose rest never came; True if one was dropped."""
        if self.pending() == 0:
            return False
        self.truncated += 1
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
        }


# -- messages (payload layouts in docs/protocol.md) ---------------------------------
# shim -> host
HELLO = 0x01  # <H proto, then UTF-8 info "version;machine"
CFG = 0x02  # <HBBBi handle, kind, mode, pull, param, then UTF-8 pin name
OUT = 0x03  # <QHBi t_us, handle, attr, value
WAIT = 0x04  # <QQI t_now_us, t_until_us, compute_us, then <H watched handles
SEEN = 0x05  # <QHI t_us, handle, sample number
UART_TX = 0x06  # <QH t_us, handle, then the bytes
FAULT = 0x07  # <Q t_us, then UTF-8 traceback
EXIT = 0x08  # <QBi t_us, kind, code
# host -> shim
WELCOME = 0x81  # <HBQ proto, mode, t_start_us
BYE = 0x83  # (empty) the host ends the session: the firmware stops at its next wait
STATE = 0x82  # <QQQH base_us, t_end_us, horizon_us, count, then count x <IHBiI dt_us, handle, kind,
#              value, extra (+ value bytes for CH_BYTES)

CFG_PIN = 1
CFG_ADC = 2
CFG_PWM = 3
CFG_UART = 4
CFG_IRQ = 5

OUT_LEVEL = 0
OUT_DUTY = 1
OUT_FREQ = 2
OUT_DEINIT = 3

CH_LEVEL = 0
CH_SAMPLE = 1
CH_BYTES = 2

EXIT_RETURN = 0
EXIT_RESET = 1
EXIT_SYSEXIT = 2

MODE_LOCKSTEP = 0
MODE_REALTIME = 1

FOREVER_US = 0xFFFFFFFFFFFFFFFF
