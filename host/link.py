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


def spare_core() -> bool:
    """True if this process may use two or more cores (one can busy-poll)."""
    try:
        return len(os.sched_getaffinity(0)) >= 2
    except AttributeError:
        return (os.cpu_count() or 1) >= 2


class FdTransport:
    """Bytes over a non-blocking file descriptor, with extra fds watched on the side
    (e.g. the firmware's console pipe) so one wait serves both.

    ``busy_poll_s`` > 0 reads the descriptor in a loop for up to that long before it
    sleeps in select(): a lockstep host whose firmware answers within a few hundred
    microseconds skips the wake-up of a sleeping process (worth it only with a core to
    spare: :func:`spare_core`)."""

    def __init__(self, fd: int, busy_poll_s: float = 0.0):
        self.fd = fd
        self.side: dict[int, callable] = {}
        self.busy_poll_s = busy_poll_s

    def watch(self, fd: int, on_data) -> None:
        os.set_blocking(fd, False)
        self.side[fd] = on_data

    def read_some(self, timeout_s: float) -> bytes:
        if self.busy_poll_s > 0.0 and timeout_s > 0.0:
            start = time.perf_counter()
            end = start + min(self.busy_poll_s, timeout_s)
            while True:
                try:
                    chunk = os.read(self.fd, 65536)
                except BlockingIOError:
                    if time.perf_counter() >= end:
                        break
                    continue
                except OSError:
                    break  # (select and read below report it)
                if chunk:
                    for fd in list(self.side):  # what the other end wrote there first is in
                        self._read_side(fd)
                    return chunk
                break
            timeout_s -= time.perf_counter() - start
        ready, _, _ = select.select([self.fd, *self.side], [], [], max(timeout_s, 0.0))
        data = b""
        for fd in ready:
            if fd != self.fd:
                self._read_side(fd)
                continue
            try:
                data = os.read(fd, 65536)
            except BlockingIOError:
                continue
            except OSError as e:  # EIO once the other end of a pty is gone
                raise LinkError(f"plant link read failed: {e}") from e
        return data

    def _read_side(self, fd: int) -> None:
        try:
            chunk = os.read(fd, 65536)
        except BlockingIOError:
            return
        except OSError:
            chunk = b""
        if chunk:
            self.side[fd](chunk)
        else:
            del self.side[fd]

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
