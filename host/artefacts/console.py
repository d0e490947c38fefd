"""The firmware's console: streamed to ``console.log`` as it arrives, with a bounded tail
kept in memory (what error messages and tests read), so a chatty firmware costs neither
memory nor time that grows with the run.

Each line of ``console.log`` starts with the virtual time it was printed at, as the
kernel's log does (``[   12.345678] text``). What the firmware prints reaches the host
before its next message; the text is stamped with the time of the next wait (the
firmware's code runs in zero virtual time between a wake-up and its next wait, and after
a print() the shim's next wait always goes to the host, even where it could have moved
its clock on alone). Text the interpreter writes itself (a traceback) carries the time of
the next wait or of the end. The tail in memory is the console as printed, without
stamps. The stamps depend on virtual time only: the same run gives the same file."""

from pathlib import Path

TAIL_BYTES = 256 * 1024
"""How much of the console's end stays in memory (``Rig.console``)."""

PENDING_BYTES = 64 * 1024
"""Past this much text without a wait, it goes to the file with the last time known."""


class ConsoleLog:
    def __init__(self, tail_bytes: int = TAIL_BYTES):
        self.tail_bytes = tail_bytes
        self._tail = bytearray()
        self._file = None
        self._line_start = True  # the next byte written to the file begins a line
        self.pending = bytearray()  # read, not yet in the file: waits for its time
        self.total_bytes = 0

    def open(self, path: Path | None) -> None:
        """Stream to ``path`` from now on (None: keep the tail only)."""
        self.close()
        self.pending.clear()
        if path is not None:
            self._file = open(path, "wb")  # noqa: SIM115  (closed by close())
            self._line_start = True

    def write(self, data: bytes, t_us: int = 0) -> None:
        """Text as read, the host's virtual time ``t_us``; it goes to the file at the next
        :meth:`stamp` (or at once, stamped ``t_us``, when that much text has no wait)."""
        self.total_bytes += len(data)
        if self._file is not None:
            self.pending += data
            if len(self.pending) > PENDING_BYTES:
                self.stamp(t_us)
        tail = self._tail
        tail += data
        if len(tail) > 2 * self.tail_bytes:  # trimmed now and then: amortised O(1) a byte
            del tail[: len(tail) - self.tail_bytes]

    @property
    def text(self) -> str:
        """The console's end (all of it, unless it outgrew ``tail_bytes``)."""
        tail = self._tail[-self.tail_bytes :] if len(self._tail) > self.tail_bytes else self._tail
        return tail.decode(errors="replace")

    def since(self, offset: int) -> tuple[str, int]:
        """(the console from byte ``offset`` on, as far as the tail still holds it; the
        offset that text starts at)."""
        first = self.total_bytes - len(self._tail)
        start = max(offset, first, self.total_bytes - self.tail_bytes)
        return self._tail[start - first :].decode(errors="replace"), start

    def stamp(self, t_us: int) -> None:
        """The pending text was printed at virtual ``t_us``: into the file with it."""
        data = bytes(self.pending)
        self.pending.clear()
        if self._file is None or not data:
            return
        stamp = b"[%11.6f] " % (t_us / 1e6)
        body = data[:-1].replace(b"\n", b"\n" + stamp) + data[-1:]
        self._file.write(stamp + body if self._line_start else body)
        self._line_start = data.endswith(b"\n")

    def close(self, t_us: int = 0) -> None:
        """Write what is pending (stamped ``t_us``) and close the file."""
        self.stamp(t_us)
        if self._file is not None:
            self._file.close()
            self._file = None


def stamped_lines(path: Path):
    """(t_us, line) for each line of a stamped ``console.log`` (an unstamped line, as
    an older trace has, carries the time of the line before it, 0 at first)."""
    t_us = 0
    with open(path, "rb") as f:
        for raw in f:
            line = raw.rstrip(b"\r\n").decode(errors="replace")
            if line.startswith("[") and "] " in line[:24]:
                head, _, rest = line.partition("] ")
                try:
                    t_us = round(float(head[1:]) * 1e6)
                    line = rest
                except ValueError:
                    pass
            yield t_us, line
