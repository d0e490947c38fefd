"""Where things are: the repository, the firmware tree, the build folder. Every module
that needs a path of the project takes it from here.

Two layouts: a checkout of the repository (``firmware/`` and ``examples/`` beside
``host/``), and the installed package, whose wheel carries them as package data under
``host/_data/`` (setup.py). Both are found from this module's own place, never from the
current directory."""

import os
from pathlib import Path

HOST = Path(__file__).resolve().parent.parent
REPO = HOST.parent
BUNDLED = HOST / "_data"
"""Our firmware and examples as the installed package carries them."""
CHECKOUT = (REPO / "pyproject.toml").is_file() and (REPO / "firmware").is_dir() and not BUNDLED.is_dir()
"""True in a checkout of the repository (an editable install too), False when installed."""
FIRMWARE = REPO / "firmware" if CHECKOUT else BUNDLED / "firmware"
EXAMPLES = REPO / "examples" if CHECKOUT else BUNDLED / "examples"
BOARDS_DIR = FIRMWARE / "boards"
BUILD = REPO / "build"
"""The project's build folder (a checkout's; nothing of an installed package is written
into site-packages: see :func:`output_root`)."""
SHIM_DIR = HOST / "shim"
"""The MicroPython side of the harness (``machine``, ``time``, ``select``, the link),
put first on the interpreter's path."""


def user_cache() -> Path:
    """The per-user cache folder of mpy-fil: ``$XDG_CACHE_HOME/mpy-fil`` (``~/.cache``
    when unset), shared between projects and virtual environments."""
    base = os.environ.get("XDG_CACHE_HOME", "").strip()
    return (Path(base) if base and Path(base).is_absolute() else Path.home() / ".cache") / "mpy-fil"


PROJECT_MARKERS = (".git", "pyproject.toml")
"""What makes a folder a user's repository root (the nearest one holding either)."""


def project_root(folder: Path) -> Path | None:
    """The user's repository ``folder`` is in: the nearest folder, ``folder`` itself or one
    above it, holding a ``.git`` or a ``pyproject.toml``; None when there is none."""
    folder = Path(folder).resolve()
    for candidate in (folder, *folder.parents):
        if any((candidate / marker).exists() for marker in PROJECT_MARKERS):
            return candidate
    return None


def output_root(rig_file: Path | None = None) -> Path:
    """Where a command writes (``build/`` under it): the project's build folder for our own
    apps and rigs in a checkout; for a rig file of the user's, ``build/`` at the root of the
    user's repository (:func:`project_root`: the nearest folder above the rig file with a
    ``.git`` or a ``pyproject.toml``; the rig file's folder when there is none), so never in
    a firmware folder of its own (``firmware/bot/build/``); where the firmware folder is the
    repository's root itself, ``build/`` is there and never put on the board
    (host/rig/targets/boardfs.py, :func:`flash_files`). Without a rig file, the current folder's
    ``build/``."""
    if rig_file is not None:
        folder = Path(rig_file).resolve().parent
        if not (CHECKOUT and folder.is_relative_to(REPO)) and not folder.is_relative_to(BUNDLED):
            return (project_root(folder) or folder) / "build"
    return BUILD if CHECKOUT else Path.cwd() / "build"


def portable(path) -> str:
    """``path`` relative to the repository when it is inside it (the same in every
    checkout: what a trace's digest may depend on), else as it is."""
    resolved = Path(path).resolve()
    try:
        return resolved.relative_to(REPO).as_posix()
    except ValueError:
        return str(resolved)
