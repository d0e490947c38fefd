"""The link log (``trace.jsonl``): one JSON object per line, virtual timestamps, deterministic content.

The trace holds what crossed the link (decoded) and what the plant reported, never
wall-clock figures, so the same (app, board, plant, seed, commit) gives the same bytes.
The firmware's console goes to its own file, since its pipe is not ordered with the
link. ``digest`` is a SHA-256 of the trace lines, kept even when no file is written.
"""

import hashlib
import json
from pathlib import Path


class LinkLog:
    def __init__(self, path: Path | None = None):
        self.path = path
        self._file = open(path, "w", encoding="utf-8") if path else None
        self._hash = hashlib.sha256()
        self.lines = 0

    def write(self, record: dict) -> None:
        line = json.dumps(record, separators=(",", ":"), sort_keys=True) + "\n"
        self._hash.update(line.encode())
        self.lines += 1
        if self._file:
            self._file.write(line)

    @property
    def digest(self) -> str:
        return self._hash.hexdigest()

    def close(self) -> None:
        if self._file:
            self._file.close()
            self._file = None
