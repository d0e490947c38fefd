"""The firmware's console: streamed to ``console.log`` as it arrives, with a bounded tail
kept in memory (what error messages and tests read), so a chatty firmware costs neither
memory nor time that grows with the run.

Each line of ``console.log`` starts with the virtual time it was printed at, as the
kernel's log does (``[   12.345678] text``). What the firmware prints reaches the host
before its next message; the text is stamped with the time of the next wait (the
firmware's code runs in zero virtual time between a wake-up and its next wait, and after
a print() the shim's next wait always goes to the host, even where it could have moved
its clock on alone). What it prints after its last wait, before it ends, and a traceback
carry the instant of the end (the rig stamps them at its EXIT or FAULT). The tail in
memory is the console as printed, without stamps. The stamps depend on virtual time only:
the same run gives the same file.

The file is flushed at each stamp, so a run killed outright (SIGKILL) leaves what was
stamped, to its last whole line. It is capped at ``max_bytes`` (the rig file's ``[trace]
console_max_bytes``, default 64 MiB): past it, the rest of the run's text is dropped,
counted (:attr:`ConsoleLog.dropped_bytes`, ``dropped_lines``) and said in the file, once at
the cap and once, with the counts, at its end. A write that fails (a full disk) raises
:class:`~host.artefacts.integrity.TraceWriteError` once; the file stays as it was cut."""

from pathlib import Path

from host.artefacts.integrity import TraceWriteError
from host.core import safefs

TAIL_BYTES = 256 * 1024
"""How much of the console's end stays in memory (``Rig.console``)."""

PENDING_BYTES = 64 * 1024
"""Past this much text without a wait, it goes to the file with the last time known."""

MAX_BYTES = 64 * 1024 * 1024
"""The console file's default cap (``[trace] console_max_bytes``)."""


class ConsoleLog:
    def __init__(self, tail_bytes: int = TAIL_BYTES, max_bytes: int = MAX_BYTES):
        self.tail_bytes = tail_bytes
        self.max_bytes = max_bytes
        self._tail = bytearray()
        self._file = None
        self.path: Path | None = None
        self._line_start = True  # the next byte written to the file begins a line
        self.pending = bytearray()  # read, not yet in the file: waits for its time
        self.total_bytes = 0
        self.file_bytes = 0  # written to the file (text and stamps)
        self.dropped_bytes = 0  # printed past the cap: not in the file
        self.dropped_lines = 0
        self.error: TraceWriteError | None = None  # the write that failed, if one did

    def open(self, path: Path | None) -> None:
        """Stream to ``path`` from now on (None: keep the tail only)."""
        self.close()
        self.pending.clear()
        self.path = path
        self.file_bytes = self.dropped_bytes = self.dropped_lines = 0
        self.error = None
        if path is not None:
            self._file = safefs.open_write(path, "wb")  # (closed by close(); a link at the name: refused)
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
        if not data:
            return
        if self._file is None or self.dropped_bytes:
            self._drop(data)
            return
        stamp = b"[%11.6f] " % (t_us / 1e6)
        body = data[:-1].replace(b"\n", b"\n" + stamp) + data[-1:]
        out = stamp + body if self._line_start else body
        if self.file_bytes + len(out) > self.max_bytes:
            self._drop(data)
            self._put(self._note(t_us, f"console.log reached its cap of {self.max_bytes} bytes; the rest is dropped"))
            return
        self._put(out)
        self._line_start = data.endswith(b"\n")

    def note(self, t_us: int, text: str) -> None:
        """A note of the harness's (a poll that never ends) on a line of its own at ``t_us``,
        after the text printed before it."""
        self.stamp(t_us)
        if self._file is not None and not self.dropped_bytes:
            self._put(self._note(t_us, text))

    def _drop(self, data: bytes) -> None:
        if self._file is not None or self.error is not None:  # (no file asked for: nothing is dropped)
            self.dropped_bytes += len(data)
            self.dropped_lines += data.count(b"\n")

    def _note(self, t_us: int, text: str) -> bytes:
        """A line of the harness's own in the file, on a line of its own."""
        return (b"" if self._line_start else b"\n") + b"[%11.6f] [mpy-fil: %s]\n" % (t_us / 1e6, text.encode())

    def _put(self, out: bytes) -> None:
        if self._file is None:
            return
        try:
            self._file.write(out)
            self._file.flush()  # (a killed run leaves what was stamped)
        except OSError as e:
            self._abandon()
            self.error = TraceWriteError(self.path, e)
            raise self.error from e
        self.file_bytes += len(out)
        self._line_start = out.endswith(b"\n")

    def _abandon(self) -> None:
        file, self._file = self._file, None
        try:
            file.close()
        except OSError:
            pass  # (what could not be flushed is lost; the error says so)

    @property
    def summary(self) -> dict:
        """For the trace header: what was printed, what the file holds, what it dropped."""
        return {
            "bytes": self.total_bytes,
            "file_bytes": self.file_bytes,
            "max_bytes": self.max_bytes,
            "dropped_bytes": self.dropped_bytes,
            "dropped_lines": self.dropped_lines,
        }

    def close(self, t_us: int = 0) -> None:
        """Write what is pending (stamped ``t_us``), the count of what was dropped, and
        close the file."""
        try:
            self.stamp(t_us)
            if self.dropped_bytes:
                counts = f"{self.dropped_bytes} bytes in {self.dropped_lines} lines dropped past the cap"
                self._put(self._note(t_us, counts))
        except TraceWriteError:
            pass  # (raised once, when it happened)
        if self._file is not None:
            try:
                self._file.close()
            except OSError as e:
                self.error = self.error or TraceWriteError(self.path, e)
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
