"""The frame codec and message layouts, as the host imports them.

One file serves both ends: ``host/shim/_hilframe.py`` runs inside MicroPython as the
shim's codec and is imported here unchanged, so the host and the shim cannot disagree
on a byte. The host's hottest read (an OUT per actuator write) uses a compiled form of
the same layout; ``host/tests/test_codec.py`` holds it to the codec's own on every vector.

The codec names every code on the wire (message types, CFG kinds, a pin's modes and
pulls, IRQ triggers, OUT attributes, STATE change kinds). The plant's signal kinds, which
never cross the link and which the shim has no use for, are named here, beside them:
the shim's heap (a board's RAM, ``heap_size``) holds no strings it never reads.
"""

import struct as _struct

from host.shim import _hilframe as codec
from host.shim._hilframe import *  # noqa: F403  (the codec's names are this module's)

unpack_out = _struct.Struct(codec.OUT_FMT).unpack_from  # (t_us, handle, attr, value), as codec.unpack_out
unpack_seen = _struct.Struct(codec.SEEN_FMT).unpack_from  # (t_us, handle, sample number), as codec.unpack_seen
# a WAIT without watched handles (shorter than WAIT_NO_WATCH_BELOW): (t_now_us, t_until_us, compute_us),
# codec.unpack_wait's but its empty watch
unpack_wait_head = _struct.Struct(codec.WAIT_FMT).unpack_from
WAIT_NO_WATCH_BELOW = codec.WAIT_LEN + codec.WATCH_LEN
# (t_us, handle) of a UART_TX, its bytes after UART_TX_LEN: codec.unpack_uart_tx's
unpack_uart_tx_head = _struct.Struct(codec.UART_TX_FMT).unpack_from

_frame_head = _struct.Struct("<BBH").pack  # type, seq, length (after the SOF)
_crc_field = _struct.Struct("<I")
_crc_at = _crc_field.unpack_from
_SOF, _HEADER_LEN, _CRC_LEN, _LONG, _crc32 = codec.SOF, codec.HEADER_LEN, codec.CRC_LEN, codec._LONG, codec.crc32


def encode(type_: int, seq: int, payload: bytes) -> bytes:
    """One frame, as ``codec.encode`` makes it (its bytes: host/tests/test_codec.py), with
    one CRC over type..payload."""
    n = len(payload)
    if n > codec.MAX_PAYLOAD:
        raise ValueError("payload of %d bytes exceeds %d" % (n, codec.MAX_PAYLOAD))
    body = _frame_head(type_, seq & 0xFF, n) + payload
    return b"\xa5" + body + _crc_field.pack(codec.crc32(body) & 0xFFFFFFFF)


# (t_us, status, count, horizon_us), the bytes read to follow: as codec.pack_bus_reply
pack_bus_reply_head = _struct.Struct(codec.BUS_REPLY_FMT).pack


class HostDecoder(codec.Decoder):
    """The codec's decoder, with the host's usual case first: a whole good frame at the
    start of what is left, the one expected next (a short one, in bytes fed at once).
    Anything else (bytes before it, a bad CRC, a gap, a duplicate, a long or partial
    frame) goes to the codec's own :meth:`next`, which takes the same frames and counts
    the same (host/tests/test_codec_properties.py)."""

    def next(self):
        got = self.next_plain()
        return got if got is not None else codec.Decoder.next(self)

    def next_plain(self, not_type: int = -1):
        """The usual case alone: the whole good frame expected next at the start of what
        is left, as (type, seq, payload), taken; else None, nothing taken (anything else
        is :meth:`next`'s). A frame of type ``not_type`` is left for :meth:`next` too."""
        buf = self.buf
        pos = self.pos
        end = pos + _HEADER_LEN
        if end <= len(buf) and buf[pos] == _SOF and not self._grown and buf[pos + 1] != not_type:
            n = buf[pos + 3] | buf[pos + 4] << 8
            end += n
            seq = buf[pos + 2]
            expect = self.expect_seq
            if (
                n < _LONG
                and end + _CRC_LEN <= len(buf)
                and (seq == expect or expect < 0)
                and _crc32(buf[pos + 1 : end]) == _crc_at(buf, end)[0]
            ):
                self.pos = end + _CRC_LEN
                self.frames += 1
                self.expect_seq = (seq + 1) & 0xFF
                return buf[pos + 1], seq, buf[pos + _HEADER_LEN : end]
        return None


def unpack_cpu(p) -> tuple:
    """A CPU message (MCU time, docs/mcu-time.md): (t_us, compute_us, piece_us, the code's
    text). (Host-side only: the shim packs it inline, _hil._cpu_stretch.)"""
    return _struct.unpack_from(codec.CPU_FMT, p, 0) + (bytes(p[codec.CPU_LEN :]).decode("utf-8", "replace"),)


unpack_cpu_irq = _struct.Struct(codec.CPU_IRQ_FMT).unpack_from  # (t_from_us, t_us, the callbacks' compute_us)


# plant signal kinds: what a plant signal carries (``plant.inputs`` / ``plant.outputs``)
SIG_LEVEL = "level"  # 0/1
SIG_U16 = "u16"  # an ADC's reading, 0..65535
SIG_DUTY = "duty"  # a PWM duty, 0..65535
SIG_PWM = "pwm"  # a PWM waveform: duty and frequency (``plant.set_pwm``)
SIG_BYTES = "bytes"  # bytes, as a whole
SIG_UART = "uart"  # bytes timed on the line at the baud rate (``plant.send_bytes``)
