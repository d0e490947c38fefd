"""Reading a trace folder back safely: a damaged one is refused by name (a ConfigError
that names the file and what is wrong), a partial one is said to be partial.

- the header's fields, each of its type and within bounds (a ``t_end_us`` of 1e30, a NaN,
  a negative seed are refused);
- the header's own digest (a header without one is damaged) and the seal of every file
  of the folder (``files``, :func:`check_seal`): a file changed, cut, missing, added after
  the run or not a regular file is named, with what differs (:class:`DamagedFolder`);
  the files' form too (a CSV that does not end with a whole line, a row of the wrong
  width);
- a file a reader needs that the run never wrote: the folder is partial (``stop`` says
  why) and the message says so rather than anything about the firmware.
"""

import math
import re
from pathlib import Path

from host.artefacts import integrity
from host.artefacts.recorder import ROLES
from host.core.errors import ConfigError

MAX_T_END_US = 10 * 24 * 3600 * 10**6  # the rig's longest run (ten simulated days)
SEED_MAX = 2**32 - 1

_INT, _TEXT, _DICT, _LIST = "an integer", "text", "a table", "a list"
_REQUIRED = {"app": _TEXT, "board": _TEXT, "mode": _TEXT, "seed": _INT, "t_end_us": _INT, "signals": _DICT}
_OPTIONAL = {
    "truth_period_us": _INT,
    "initial": _DICT,
    "plant_options": _DICT,
    "contacts": _LIST,
    "incomplete": _DICT,
    "files": _DICT,
    "faults": _LIST,
    "spec": _DICT,
}
HEADER = "header.json"  # (host.artefacts.folder.HEADER)
SHOWN = 8  # a damaged folder's files named in its one message
_SHA256 = re.compile(r"[0-9a-f]{64}")


class DamagedFolder(ConfigError):
    """A trace folder whose seal does not hold: a file changed, cut, missing or added after
    the run, or a header without its digest. The message names each file and what differs."""


_BOUNDS = {"seed": (0, SEED_MAX), "t_end_us": (0, MAX_T_END_US), "truth_period_us": (1, MAX_T_END_US)}


def _kind_ok(value, kind: str) -> bool:
    if kind == _INT:
        return type(value) is int
    return isinstance(value, {_TEXT: str, _DICT: dict, _LIST: list}[kind])


def check_header(folder: Path, header) -> None:
    """Every field a reader uses, of its type and in bounds; the header's own digest."""
    where = f"trace folder {folder}: header.json"
    if not isinstance(header, dict):
        raise ConfigError(f"{where}: expected a JSON object, got {type(header).__name__}")
    if "digest" not in header:
        raise DamagedFolder(
            f"{where}: no 'digest' (every header a run writes is sealed: this one was edited or damaged after the run)"
        )
    if header["digest"] != integrity.header_digest(header):
        raise DamagedFolder(f"{where}: its digest does not match its fields (changed or damaged after the run)")
    for name, kind in {**_REQUIRED, **_OPTIONAL}.items():
        if name not in header:
            if name in _REQUIRED:
                raise ConfigError(f"{where}: no {name!r} (expected the header a recorded run writes)")
            continue
        value = header[name]
        if not _kind_ok(value, kind):
            raise ConfigError(f"{where}: {name} expected {kind}, got {value!r:.80}")
        low, high = _BOUNDS.get(name, (None, None))
        if low is not None and not low <= value <= high:
            raise ConfigError(f"{where}: {name} expected {low} to {high}, got {value}")
    _check_signals(where, header["signals"])
    for name in ("footprint_half_width_m", "coverage_cell_m"):
        value = header.get(name, 1.0)
        if type(value) not in (int, float) or not math.isfinite(value) or value <= 0 or value > 1e6:
            raise ConfigError(f"{where}: {name} expected a positive finite number of metres, got {value!r:.80}")
    for name, kinds in (("stop", (dict, type(None))), ("rig_file", (str, type(None))), ("partial", (bool,))):
        if name in header and not isinstance(header[name], kinds):
            raise ConfigError(f"{where}: {name} expected {kinds[0].__name__} or null, got {header[name]!r:.80}")


def _check_signals(where: str, signals: dict) -> None:
    for name, info in signals.items():
        if not isinstance(info, dict) or info.get("role") not in ROLES or not isinstance(info.get("kind"), str):
            raise ConfigError(f"{where}: signals {name!r:.60} expected {{role, kind}}, got {info!r:.80}")


def partial_reason(header: dict) -> str | None:
    """Why a folder is partial ("stopped by SIGTERM at t=12.5 s"), None when it is whole."""
    if not header.get("partial"):
        return None
    stop = header.get("stop") or {}
    reason = str(stop.get("reason") or "files incomplete")
    t_us = stop.get("t_us", header.get("t_end_us")) if stop.get("signal") or not stop else stop.get("t_us")
    if type(t_us) in (int, float):
        reason += f", at t={t_us / 1e6:g} s"
    incomplete = header.get("incomplete") or {}
    if incomplete:
        reason += f"; incomplete: {', '.join(sorted(incomplete))} (header.json says why)"
    return reason


def check_seal(folder: Path, header: dict) -> None:
    """Every file of the folder against the header's seal (``files``: each file's SHA-256,
    :func:`host.artefacts.integrity.folder_digests`): one :class:`DamagedFolder` naming
    each file missing, changed or cut (its size and digest against the sealed one), added
    after the run, or not a regular file (a link, a FIFO). A run that did not end sealed
    nothing: the folder is refused as partial. Every command that reads a trace folder
    calls this (through :func:`host.artefacts.folder.load_trace`)."""
    where = f"trace folder {folder}"
    files = header.get("files")
    if files is None:
        partial = partial_reason(header)
        if partial:  # (a run killed outright: its header, written as it began, names no file)
            raise ConfigError(f"{where}: no signals.csv; the folder is partial: {partial} ({HEADER} seals no files)")
        raise DamagedFolder(f"{where}: {HEADER} seals no files (no 'files'); expected the header a recorded run writes")
    problems = []
    for name, digest in files.items():
        if digest is None:
            problems.append(f"{name}: sealed with no digest (a folder written before every file was sealed)")
        elif not isinstance(digest, str) or not _SHA256.fullmatch(digest):
            problems.append(f"{name!r:.80}: header.json's digest {digest!r:.80} is not a SHA-256")
        elif not _sealable(name):
            problems.append(f"{name!r:.80}: not a name inside the folder")
    entries = integrity.folder_entries(folder, HEADER)
    for name, digest in files.items():
        if not _sealable(name):
            continue
        path = entries.get(name)
        if path is None:
            problems.append(f"{name}: missing (header.json seals it)")
        elif path.is_symlink() or not path.is_file():
            problems.append(f"{name}: not a regular file (a link or a device): expected the file the run wrote")
        elif isinstance(digest, str) and (got := integrity.file_digest(path)) != digest:
            problems.append(
                f"{name} does not match its digest in header.json (changed or cut after the run: "
                f"{path.stat().st_size} bytes, SHA-256 {got[:12]}..., sealed {digest[:12]}...)"
            )
    for name, path in entries.items():
        if name not in files:
            kind = "a link" if path.is_symlink() else "a file" if path.is_file() else "not a regular file"
            problems.append(f"{name}: {kind} added after the run (header.json does not seal it)")
    if problems:
        shown = "; ".join(problems[:SHOWN]) + (f"; and {len(problems) - SHOWN} more" if len(problems) > SHOWN else "")
        raise DamagedFolder(f"{where}: damaged, its seal does not hold: {shown}")


def _sealable(name) -> bool:
    """A name ``files`` may hold: a relative path inside the folder (no ``..``)."""
    if not isinstance(name, str) or not name or name.startswith("/") or "\\" in name or "\0" in name:
        return False
    return all(part not in ("", ".", "..") for part in name.split("/"))


def check_file(folder: Path, header: dict, name: str, needed: bool) -> bool:
    """Whether ``name`` is there to be read. A file whose digest the header holds must
    match it; one the reader ``needed`` that is absent is named (and the folder's partial
    state with it)."""
    path = folder / name
    files = header.get("files")
    if not path.is_file():
        if isinstance(files, dict) and name in files:
            raise ConfigError(f"trace folder {folder}: {name} is missing (header.json lists it)")
        if needed:
            partial = partial_reason(header)
            why = f"the folder is partial: {partial}" if partial else "expected the files a recorded run writes"
            raise ConfigError(f"trace folder {folder}: no {name}; {why}")
        return False
    digest = files.get(name) if isinstance(files, dict) else None
    if digest is not None and integrity.file_digest(path) != digest:
        raise ConfigError(
            f"trace folder {folder}: {name} does not match its digest in header.json (changed or cut after the run)"
        )
    return True


def whole_lines(folder: Path, name: str, text: str) -> None:
    """A file of lines must end with a whole one (a file cut short does not)."""
    if text and not text.endswith("\n"):
        raise ConfigError(f"trace folder {folder}: {name} ends in the middle of a line (cut short)")
