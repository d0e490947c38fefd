"""Reading a trace folder back safely: a damaged one is refused by name (a ConfigError
that names the file and what is wrong), a partial one is said to be partial.

- the header's fields, each of its type and within bounds (a ``t_end_us`` of 1e30, a NaN,
  a negative seed are refused);
- the header's own digest and each file's (``files``): a file changed, cut or missing
  after the run is named; a folder written before digests is checked by its form alone
  (a CSV that does not end with a whole line, a row of the wrong width);
- a file a reader needs that the run never wrote: the folder is partial (``stop`` says
  why) and the message says so rather than anything about the firmware.
"""

import math
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
}
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
    if "digest" in header and header["digest"] != integrity.header_digest(header):
        raise ConfigError(f"{where}: its digest does not match its fields (changed or damaged after the run)")
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
