"""The pty's own round trip, as a yardstick: CPython writes a frame's worth of bytes to a
raw pty, MicroPython's unix port answers with a reply's worth, nothing decoded on either
side. Both ends wait the way the link does (the far end in ``poll()`` then ``read``, the
host in a busy read or ``select()``), so what is left of a link exchange beyond this is the
harness's own work (``docs/clock.md``, ``make bench``)."""

import os
import select
import subprocess
import time

from host.core.children import popen_options
from host.core.errors import LinkTimeout
from host.link.pty import PtyPair

# The far end: wait for `n_in` bytes, answer `n_out`, until the link closes.
_PONG = """
import select, sys
f = open(sys.argv[1], "r+b")
p = select.poll()
p.register(f, select.POLLIN)
n_in = int(sys.argv[2])
reply = bytes(int(sys.argv[3]))
got = 0
while True:
    ev = p.poll(1000)
    if ev and ev[0][1] & (select.POLLHUP | select.POLLERR):
        break
    d = f.read(512)
    if d is None:
        continue
    if not d:
        break
    got += len(d)
    while got >= n_in:
        f.write(reply)
        got -= n_in
"""


def round_trips_us(
    micropython: str, n: int, out_len: int, reply_len: int, busy_poll_s: float = 0.0, timeout_s: float = 5.0
) -> list[float]:
    """``n`` round trips of ``out_len`` bytes out and ``reply_len`` bytes back, each in
    microseconds of wall time (the first 50, warm-up, left out)."""
    pty = PtyPair()
    proc = subprocess.Popen(
        [micropython, "-c", _PONG, pty.slave_path, str(out_len), str(reply_len)],
        stdin=subprocess.DEVNULL,
        **popen_options(),
    )
    try:
        return _measure(pty.master_fd, n + 50, bytes(out_len), reply_len, busy_poll_s, timeout_s)[50:]
    finally:
        proc.kill()
        proc.wait(timeout=5)
        pty.close()


def _measure(fd: int, n: int, out: bytes, reply_len: int, busy_poll_s: float, timeout_s: float) -> list[float]:
    times = []
    perf = time.perf_counter
    for _ in range(n):
        t0 = perf()
        os.write(fd, out)
        got = 0
        while got < reply_len:
            got += len(_read(fd, t0, busy_poll_s, timeout_s))
        times.append((perf() - t0) * 1e6)
    return times


def _read(fd: int, t0: float, busy_poll_s: float, timeout_s: float) -> bytes:
    perf = time.perf_counter
    end = perf() + busy_poll_s
    while True:
        try:
            return os.read(fd, 65536)
        except BlockingIOError:
            if perf() >= end:
                break
    left = t0 + timeout_s - perf()
    if left <= 0 or not select.select([fd], [], [], left)[0]:
        raise LinkTimeout(f"raw pty ping-pong: no reply within {timeout_s} s")
    return os.read(fd, 65536)
