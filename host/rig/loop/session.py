"""The conversation with the shim on one channel: the handshake, frames sent, frames
received under a deadline, and what came last (for the watchdog's message).

A receive that gets nothing in time, or a link that fails, goes to ``on_silence``
(the target's: a hung firmware, a process that ended, a board that went quiet).
"""

import time

from host.core.errors import LinkDamaged, LinkError, LinkTimeout
from host.link import frames as F

HANDSHAKE_TIMEOUT_S = 10.0


class Session:
    def __init__(self, on_silence, round_trip_us: list | None = None, on_damage=None, taken_us: list | None = None):
        self.on_silence = on_silence  # (timeout_s, what) -> raises
        self.on_damage = on_damage  # (LinkDamaged) -> raises: a frame was damaged or lost
        # STATE -> WAIT wall times, when timed: from the STATE's write to the read that brought
        # the WAIT's bytes (the firmware's wake and work, the pty both ways); what the host does
        # with the frames before the WAIT (an OUT's handling) is the host's share, not in it
        self.round_trip_us = round_trip_us
        self.taken_us = taken_us  # (with it: from the STATE's write to the WAIT taken, the OUT's handling in)
        self.chan = None
        self.last_type: int | None = None  # of the last message from the shim
        self.last_sent_type: int | None = None  # of the last message to it
        self._t_sent = None

    def handshake(self, chan, mode: int, t_us: int, settings: dict, zero_delay=False) -> str:
        """HELLO from the shim, WELCOME back; the shim's "<micropython version>;<machine>".
        ``settings``: the shim's, as the codec packs them (ShimSettings.packed, with the
        board's identity); ``zero_delay``: the plant's wires carry a write to an input at once."""
        self.chan = chan
        self.last_type = self.last_sent_type = None  # (of this boot's conversation)
        type_, payload = self.recv(HANDSHAKE_TIMEOUT_S, "HELLO")
        if type_ != F.HELLO:
            raise LinkError(f"expected HELLO from the shim, got {F.NAMES.get(type_, hex(type_))}")
        proto, info = F.unpack_hello(payload)
        if proto != F.PROTO_VERSION:
            raise LinkError(f"shim speaks link protocol {proto}, host speaks {F.PROTO_VERSION}")
        flags = F.WELCOME_ZERO_DELAY if zero_delay else 0
        self.send(F.WELCOME, F.pack_welcome(mode, t_us, flags, settings))
        return info.decode(errors="replace")

    def send(self, type_: int, payload: bytes) -> None:
        self.last_sent_type = type_
        # (timed from before the write, as the raw round trip is: the clock of the channel's last_data_wall)
        t_sent = time.monotonic() if self.round_trip_us is not None else None
        try:
            self.chan.send(type_, payload)
        except OSError as e:
            raise LinkError(f"plant link write failed: {e}") from e
        if t_sent is not None:
            self._t_sent = t_sent

    def hold(self, type_: int, payload: bytes) -> None:
        """A frame sent with the next one, in one write."""
        self.chan.hold(type_, payload)

    def recv(self, timeout_s: float, what: str):
        """The next message as (type, payload); silence is the target's to report."""
        try:
            type_, _seq, payload = self.chan.recv(timeout_s)
        except LinkTimeout:
            self.on_silence(timeout_s, what)
        except LinkDamaged as e:
            if self.on_damage is None:
                raise
            self.on_damage(e)
        except LinkError:
            self.on_silence(0, what)
        if self._t_sent is not None and type_ == F.WAIT:
            self.round_trip_us.append((self.chan.last_data_wall - self._t_sent) * 1e6)
            if self.taken_us is not None:
                self.taken_us.append((time.monotonic() - self._t_sent) * 1e6)
            self._t_sent = None
        self.last_type = type_
        return type_, payload

    def poll(self, timeout_s: float, despite_damage: bool = False):
        """The next message, or None if none came within ``timeout_s``. ``despite_damage``:
        after a lost or damaged frame too (the link's counters keep the loss)."""
        recv = self.chan.recv_despite_damage if despite_damage else self.chan.recv
        try:
            type_, _seq, payload = recv(timeout_s)
        except LinkTimeout:
            return None
        self.last_type = type_
        return type_, payload

    def last_message(self) -> str:
        if self.last_type is None:
            return "none yet"
        name = F.NAMES.get(self.last_type, hex(self.last_type))
        wall = self.chan.last_data_wall if self.chan else None
        return name if wall is None else f"{name}, {time.monotonic() - wall:.1f} s of wall time ago"

    def last_sent(self) -> str:
        return F.NAMES.get(self.last_sent_type, "nothing") if self.last_sent_type is not None else "nothing"

    def counters(self) -> dict:
        return self.chan.counters() if self.chan else {}
