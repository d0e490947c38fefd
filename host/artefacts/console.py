"""The firmware's console: streamed to ``console.log`` as it arrives, with a bounded tail
kept in memory (what error messages and tests read), so a chatty firmware costs neither
memory nor time that grows with the run."""

from pathlib import Path

TAIL_BYTES = 256 * 1024
"""How much of the console's end stays in memory (``Rig.console``)."""


class ConsoleLog:
    def __init__(self, tail_bytes: int = TAIL_BYTES):
        self.tail_bytes = tail_bytes
        self._tail = bytearray()
        self._file = None
        self.total_bytes = 0

    def open(self, path: Path | None) -> None:
        """Stream to ``path`` from now on (None: keep the tail only)."""
        self.close()
        if path is not None:
            self._file = open(path, "wb")  # noqa: SIM115  (closed by close())

    def write(self, data: bytes) -> None:
        self.total_bytes += len(data)
        if self._file is not None:
            self._file.write(data)
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

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None
