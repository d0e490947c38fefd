"""Framed messages over a transport: the codec shared with the shim
(``host/shim/_hilframe.py``), a sequence number per direction, and a deadline on every
receive. The byte layout is in ``docs/protocol.md``."""

import time

from host.core.errors import LinkDamaged, LinkError, LinkTimeout
from host.link import frames

TRUNCATION_TIMEOUT_S = 0.05
"""A partial frame that gets no more bytes for this long is dropped as truncated."""


class Channel:
    """Framed messages over a transport. Every receive has a deadline."""

    def __init__(self, transport):
        self.transport = transport
        self.decoder = frames.HostDecoder()
        self.seq = 0
        self.sent = 0
        self.held = b""  # frames to go out with the next one sent (hold)
        self.last_data_wall: float | None = None  # time.monotonic() of the last bytes read
        self.closed_read = False  # one more read after the console closed, for the last frames

    def send(self, type_: int, payload: bytes) -> bytes:
        data = frames.encode(type_, self.seq, payload)
        self.seq = (self.seq + 1) & 0xFF
        held, self.held = self.held, b""
        self.transport.write(held + data if held else data)
        self.sent += 1
        return data

    def hold(self, type_: int, payload: bytes) -> None:
        """A frame that goes out with the next one sent, in the same write (a BUS_IMAGE)."""
        self.held += frames.encode(type_, self.seq, payload)
        self.seq = (self.seq + 1) & 0xFF
        self.sent += 1

    def recv(self, timeout_s: float):
        """The next good frame (type, seq, payload); LinkTimeout if none by the deadline;
        LinkDamaged as soon as a frame was damaged or lost (a duplicate is dropped)."""
        decoder = self.decoder
        got = decoder.next() if decoder.pos < len(decoder.buf) else None  # (a read brings several frames at once)
        if got is None:
            got = self._recv(timeout_s, fed=False)
        if self.decoder.damaged:
            raise LinkDamaged(self.damage_report("from the firmware"))
        return got

    def recv_despite_damage(self, timeout_s: float):
        """The next good frame, even after a gap or a damaged frame (what the firmware
        says when interrupted, with a lost frame before it); LinkTimeout if none."""
        return self._recv(timeout_s, strict=False)

    def damage_report(self, direction: str) -> str:
        c = self.counters()
        lost = {k: c[k] for k in ("bad_crc", "bad_length", "truncated", "seq_gaps") if c[k]}
        return (
            f"a frame {direction} was damaged or lost on the plant link "
            f"({', '.join(f'{k}={v}' for k, v in lost.items()) or 'no counter'}; good frames {c['frames']}, "
            f"duplicates dropped {c['duplicates']}): the run cannot be trusted past it"
        )

    def _recv(self, timeout_s: float, strict: bool = True, fed: bool = True):
        """``fed``: bytes may have come since the decoder was last asked (False: it was
        just asked, and holds no whole frame)."""
        deadline = time.monotonic() + timeout_s
        stalled_since = None
        while True:
            if fed:  # (the usual frame first, without next's call; anything else the codec's)
                got = self.decoder.next_plain()
                if got is None:
                    got = self.decoder.next()
                if got is not None:
                    return got
            fed = True
            if strict and self.decoder.damaged:  # (a damaged frame with nothing after it: say so now)
                raise LinkDamaged(self.damage_report("from the firmware"))
            now = time.monotonic()
            if now >= deadline:
                pending = self.decoder.pending()
                raise LinkTimeout(f"no frame within {timeout_s:.3g} s ({pending} bytes of a partial frame)")
            wait = deadline - now
            if self.transport.side_closed:  # the process is gone: what it wrote is in, or never comes
                if self.closed_read:
                    raise LinkError("the firmware's console closed: its process ended")
                self.closed_read = True
                wait = min(wait, TRUNCATION_TIMEOUT_S)
            if self.decoder.pos < len(self.decoder.buf):  # (a partial frame pending)
                stalled_since = stalled_since or now
                if now - stalled_since >= TRUNCATION_TIMEOUT_S:
                    self.decoder.expire()
                    stalled_since = None
                    continue
                wait = min(wait, TRUNCATION_TIMEOUT_S)
            data = self.transport.read_some(wait)
            if data:
                self.decoder.feed(data)
                self.last_data_wall = time.monotonic()
                stalled_since = None

    def counters(self) -> dict:
        return {"sent": self.sent, **self.decoder.counters()}
