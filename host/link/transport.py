"""Bytes over a non-blocking file descriptor, with deadlines (the pty's master end, or a
board's serial port)."""

import os
import select
import time

from host.core.errors import LinkError, LinkTimeout

BUSY_POLL_ENV = "MPY_FIL_BUSY_POLL"


def cores() -> int:
    """The cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


def spare_core() -> bool:
    """True if this process may use two or more cores (one can busy-poll). Whether it
    should is the front end's choice (``RigSpec.busy_poll``; ``MPY_FIL_BUSY_POLL=0`` read
    once there: :func:`busy_poll_wanted`)."""
    return cores() >= 2


def busy_poll_wanted(environ=os.environ) -> bool:
    """The user's switch, read by the front ends only (the CLI, the pytest plugin, the
    benchmarks): ``MPY_FIL_BUSY_POLL=0`` forbids spinning on the link."""
    return environ.get(BUSY_POLL_ENV) != "0"


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
        self.side_closed = False  # a side fd reached its end (the firmware's console: it exited)

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
            self.side_closed = True

    def write(self, data: bytes, timeout_s: float = 5.0) -> None:
        try:  # (the usual case: the pty takes the frames at once, whole)
            n = os.write(self.fd, data)
        except BlockingIOError:
            n = 0
        if n == len(data):
            return
        deadline = time.monotonic() + timeout_s
        view = memoryview(data)[n:]
        while view:
            try:
                n = os.write(self.fd, view)
                view = view[n:]
            except BlockingIOError:
                if time.monotonic() > deadline:
                    raise LinkTimeout(f"plant link write blocked for {timeout_s} s") from None
                select.select([], [self.fd], [], 0.01)
