"""Where things are: the repository, the firmware tree, the build folder. Every module
that needs a path of the project takes it from here."""

from pathlib import Path

REPO = Path(__file__).resolve().parent.parent.parent
FIRMWARE = REPO / "firmware"
BOARDS_DIR = FIRMWARE / "boards"
BUILD = REPO / "build"
HOST = REPO / "host"
SHIM_DIR = HOST / "shim"
"""The MicroPython side of the harness (``machine``, ``time``, ``select``, the link),
put first on the interpreter's path."""


def portable(path) -> str:
    """``path`` relative to the repository when it is inside it (the same in every
    checkout: what a trace's digest may depend on), else as it is."""
    resolved = Path(path).resolve()
    try:
        return resolved.relative_to(REPO).as_posix()
    except ValueError:
        return str(resolved)
