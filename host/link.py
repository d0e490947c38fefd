"""The plant link on the host side: a raw pty pair and a framed channel with deadlines.

The byte layout is in ``docs/protocol.md``; the codec itself is shared with the shim
(``host/shim/_hilframe.py``) so both ends run the same code.
"""

import os
import select
import termios
import time
import tty

from host.errors import LinkError, LinkTimeout
from host.shim import _hilframe as frame

TRUNCATION_TIMEOUT_S = 0.05
"""A partial frame that gets no more bytes for this long is dropped as truncated."""


def _raw(fd: int, vmin: int = 0) -> None:
    tty.setraw(fd)
    attrs = termios.tcgetattr(fd)
    attrs[6][termios.VMIN] = vmin  # 0: reads return what is there (MicroPython's read(n)
    attrs[6][termios.VTIME] = 0  # would otherwise block until all n bytes arrive)
    termios.tcsetattr(fd, termios.TCSANOW, attrs)


class PtyPair:
    """A pseudo-terminal pair in raw mode; the firmware opens ``slave_path``.

    ``console=True`` makes the slave a board console instead of a link: blocking
    one-byte reads."""

    def __init__(self, console: bool = False):
        self.master_fd, self.slave_fd = os.openpty()
        _raw(self.slave_fd, vmin=1 if console else 0)  # one termios for both ends
        os.set_blocking(self.master_fd, False)
        self.slave_path = os.ttyname(self.slave_fd)

    def close(self) -> None:
        for fd in (self.master_fd, self.slave_fd):
            if fd >= 0:
                try:
                    os.close(fd)
                except OSError:
                    pass
        self.master_fd = self.slave_fd = -1


class FdTransport:
    """Bytes over a non-blocking file descriptor, with extra fds watched on the side
    (e.g. the firmware's console pipe) so one wait serves both."""

    def __init__(self, fd: int):
        self.fd = fd
        self.side: dict[int, callable] = {}

    def watch(self, fd: int, on_data) -> None:
        os.set_blocking(fd, False)
        self.side[fd] = on_data

    def read_some(self, timeout_s: float) -> bytes:
        fds = [self.fd, *self.side]
        ready, _, _ = select.select(fds, [], [], max(timeout_s, 0.0))
        data = b""
        for fd in ready:
            try:
                chunk = os.read(fd, 65536)
            except BlockingIOError:
                continue
            except OSError as e:  # EIO once the other end of a pty is gone
                if fd == self.fd:
                    raise LinkError(f"plant link read failed: {e}") from e
                chunk = b""
            if fd == self.fd:
                data = chunk
            elif chunk:
                self.side[fd](chunk)
            else:
                del self.side[fd]
        return data

    def write(self, data: bytes, timeout_s: float = 5.0) -> None:
        deadline = time.monotonic() + timeout_s
        view = memoryview(data)
        while view:
            try:
                n = os.write(self.fd, view)
                view = view[n:]
            except BlockingIOError:
                if time.monotonic() > deadline:
                    raise LinkTimeout(f"plant link write blocked for {timeout_s} s") from None
                select.select([], [self.fd], [], 0.01)


class Channel:
    """Framed messages over a transport. Every receive has a deadline."""

    def __init__(self, transport):
        self.transport = transport
        self.decoder = frame.Decoder()
        self.seq = 0
        self.sent = 0
        self.last_data_wall: float | None = None  # time.monotonic() of the last bytes read

    def send(self, type_: int, payload: bytes) -> bytes:
        data = frame.encode(type_, self.seq, payload)
        self.seq = (self.seq + 1) & 0xFF
        self.transport.write(data)
        self.sent += 1
        return data

    def recv(self, timeout_s: float):
        """The next good frame (type, seq, payload); LinkTimeout if none by the deadline."""
        got = self.decoder.next()
        if got is not None:  # (a read brings several frames at once)
            return got
        deadline = time.monotonic() + timeout_s
        stalled_since = None
        while True:
            got = self.decoder.next()
            if got is not None:
                return got
            now = time.monotonic()
            if now >= deadline:
                pending = self.decoder.pending()
                raise LinkTimeout(f"no frame within {timeout_s:.3g} s ({pending} bytes of a partial frame)")
            wait = deadline - now
            if self.decoder.pending():
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
