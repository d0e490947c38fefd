"""Trace files that are either complete or say they are not (``docs/traces.md``).

- :class:`Stopped`: the run was stopped by a signal (SIGTERM, SIGHUP; SIGINT is Python's
  own KeyboardInterrupt); the trace folder is written, marked partial.
- :class:`TraceWriteError`: a file of the run could not be written (a full disk): one
  message naming the path; the run ends and what is left is marked.
- :func:`atomic`: a file written under a temporary name and renamed when whole, so a file
  under its own name is never cut short (a cut one is removed, its space given back).
- :func:`file_digest` and :func:`seal`: the SHA-256 of each file and of the header
  itself, so a reader can tell a damaged folder from a firmware that changed;
  :func:`folder_digests` every file of a trace folder (its top level and ``board_fs/``),
  what the header seals and :func:`host.artefacts.checks.check_seal` checks.
"""

import hashlib
import json
import os
from contextlib import contextmanager
from pathlib import Path

from host.core.errors import HarnessError
from host.core.safefs import fresh_file
from host.core.stop_signals import Stopped  # noqa: F401  (where the run's callers look for it)

PART = ".part"  # a file being written; never left behind by a run that ends


def stop_signal_name(error: BaseException) -> str:
    """The signal that stopped a run (``SIGINT`` for a plain KeyboardInterrupt)."""
    return getattr(error, "signal_name", "SIGINT")


class TraceWriteError(HarnessError):
    """A file of the run could not be written (full disk, read-only, quota)."""

    def __init__(self, path: Path, error: OSError):
        self.path = Path(path)
        self.error = error
        reason = error.strerror or str(error)
        super().__init__(
            f"cannot write {path}: {reason}; the run stopped there and its trace folder "
            f"{self.path.parent} is marked partial (header.json lists the incomplete files)"
        )


@contextmanager
def atomic(path: Path):
    """Yields a temporary path beside ``path``; renamed to ``path`` once the block ends
    without error, removed otherwise (an OSError becomes a TraceWriteError naming ``path``)."""
    part = path.with_name(path.name + PART)
    try:
        fresh_file(part)  # (a link left at the name is removed, never written through)
        yield part
        os.replace(part, path)
    except BaseException as e:
        part.unlink(missing_ok=True)
        if isinstance(e, OSError):
            raise TraceWriteError(path, e) from e
        raise


def write_text(path: Path, text: str) -> None:
    """``text`` into ``path``, whole or not at all."""
    with atomic(path) as part:
        part.write_text(text, encoding="utf-8")


def file_digest(path: Path) -> str:
    with open(path, "rb") as f:
        return hashlib.file_digest(f, "sha256").hexdigest()


SEALED_FOLDERS = ("board_fs",)
"""Subfolders a run writes into its trace folder, sealed with it; the others (``plots/``,
``replay/``, ``diff/``, ``coverage/``) are what later commands make from it."""


def folder_entries(folder: Path, header_name: str) -> dict[str, Path]:
    """Every entry of a trace folder that its seal covers, by its name in ``files``
    (``board_fs/log.txt``): the top level's files (links and other non-directories
    included, so a reader can refuse them by name) but ``header_name`` and ``.part``
    files, and everything under :data:`SEALED_FOLDERS`."""
    folder = Path(folder)
    found: dict[str, Path] = {}
    for path in sorted(folder.iterdir()):
        name = path.name
        if name == header_name or name.endswith(PART):
            continue
        if path.is_dir() and not path.is_symlink():
            if name in SEALED_FOLDERS:
                for inner in sorted(path.rglob("*")):
                    if inner.is_symlink() or not inner.is_dir():
                        found[inner.relative_to(folder).as_posix()] = inner
            continue
        found[name] = path
    return found


def folder_digests(folder: Path, header_name: str) -> dict[str, str]:
    """The SHA-256 of every regular file :func:`folder_entries` lists (what the header
    seals); an entry that is not a regular file is left out, so a reader names it."""
    return {
        name: file_digest(path)
        for name, path in folder_entries(folder, header_name).items()
        if path.is_file() and not path.is_symlink()
    }


def header_digest(header: dict) -> str:
    """The SHA-256 of the header's own fields (all but ``digest``), canonical JSON."""
    body = {k: v for k, v in header.items() if k != "digest"}
    text = json.dumps(body, sort_keys=True, separators=(",", ":"), allow_nan=True)
    return hashlib.sha256(text.encode()).hexdigest()


def seal(header: dict) -> dict:
    """The header with its own digest."""
    return {**header, "digest": header_digest(header)}


def remove_stale(folder: Path, names) -> None:
    """An earlier run's files of these names (and their ``.part``), so a folder never
    mixes two runs."""
    for name in names:
        (folder / name).unlink(missing_ok=True)
        (folder / (name + PART)).unlink(missing_ok=True)
