"""The board's flash for one run: a per-run copy of the firmware, which the shim mounts at /.

Each run gets the files a board would have after ``make flash`` (the entry, ``boot.py``,
the app's modules and data files at ``/``, its libraries, the pin map and the project's
drivers in ``/lib``: the files the firmware's identity hashes, :meth:`Firmware.files`,
and the firmware folder's subfolders) in a folder of its own; the shim
(``host/shim/_hilfs.py``) maps every path the firmware names into it, so writes never
touch the user's sources. At the end, what the firmware wrote (files created or changed)
is kept in the trace folder's ``board_fs/`` and listed.

The rig file's ``[board]`` table sets the flash (``flash_size``, default an ESP32's
2 MiB filesystem partition of its 4 MB flash), the host modules a port has
(``allow_modules = {_thread = "the ESP32 port has threads"}``: each with its reason) and
whether the sandbox is required (``sandbox = "require"``, docs/security.md).
"""

import hashlib
import os
import re
import shutil
import tempfile
from dataclasses import dataclass
from pathlib import Path

from host.core import safefs

DEFAULT_FLASH_BYTES = 2 * 1024 * 1024  # MicroPython's ESP32 build: the vfs partition of 4 MB
FLASH_MIN_BYTES, FLASH_MAX_BYTES = 16 * 1024, 1 << 30
SIZE = re.compile(r"(\d+|0x[0-9a-fA-F]+)([kKmM]?)")
ALLOWABLE = (
    "ffi",
    "socket",
    "usocket",
    "_thread",
    "termios",
    "os.system",
    "os.getenv",
    "os.putenv",
    "os.unsetenv",
    "os.errno",
    "os.unlink",
    "vfs.VfsPosix",
    "os.VfsPosix",
)
SANDBOX_CHOICES = ("auto", "require", "off")


def flash_bytes(where, board: dict) -> int:
    """``[board] flash_size``: bytes, an integer or text like ``2M``, ``512K``."""
    size = board.get("flash_size", DEFAULT_FLASH_BYTES)
    match = SIZE.fullmatch(str(size)) if not isinstance(size, bool) else None
    expected = f"expected bytes from {FLASH_MIN_BYTES // 1024}K to {FLASH_MAX_BYTES >> 20}M, like 2M or 512K"
    if not match:
        raise where.error("[board] flash_size", f"{expected}, got {size!r}")
    number, unit = match.groups()
    value = int(number, 0) * {"": 1, "k": 1024, "m": 1 << 20}[unit.lower()]
    if not FLASH_MIN_BYTES <= value <= FLASH_MAX_BYTES:
        raise where.error("[board] flash_size", f"{expected}, got {size!r} ({value} bytes)")
    return value


def allowed_modules(where, board: dict) -> tuple[str, ...]:
    """``[board] allow_modules = {name = "reason"}``: host modules the board's port has."""
    table = board.get("allow_modules", {})
    if not isinstance(table, dict):
        raise where.error("[board] allow_modules", f'expected a table like {{_thread = "reason"}}, got {table!r}')
    for name, reason in table.items():
        if name not in ALLOWABLE:
            raise where.error("[board] allow_modules", f"{name!r} is not one of {', '.join(ALLOWABLE)}")
        if not isinstance(reason, str) or not reason.strip():
            raise where.error(f"[board] allow_modules {name}", "expected the reason, as text (which port has it)")
    return tuple(table)


def sandbox_setting(where, board: dict) -> str:
    value = board.get("sandbox", "auto")
    if value not in SANDBOX_CHOICES:
        raise where.error("[board] sandbox", f"expected one of {', '.join(SANDBOX_CHOICES)}, got {value!r}")
    return value


@dataclass(frozen=True)
class Confinement:
    """What the board lets the firmware do (``[board] flash_size``, ``allow_modules``,
    ``sandbox``: docs/security.md)."""

    flash_bytes: int = DEFAULT_FLASH_BYTES
    allow: tuple[str, ...] = ()  # host modules the board's port has
    sandbox: str = "auto"  # SANDBOX_CHOICES


def confinement(where, board) -> Confinement:
    """The ``[board]`` settings of the firmware's confinement, for ``App.board``."""
    board = board if isinstance(board, dict) else {}
    return Confinement(flash_bytes(where, board), allowed_modules(where, board), sandbox_setting(where, board))


def board_name(label: str) -> str:
    """Where a file of :meth:`Firmware.files` lies on the board: the first folder's
    (and the entry) at /, the others' in /lib."""
    where, _, rel = label.partition(":")
    return rel if where in ("entry", "0") else f"lib/{rel}"


def on_board(firmware) -> dict[str, Path]:
    """The board's flash as ``make flash`` writes it: board path -> the file it comes from,
    for the per-run copy (:class:`BoardFs`), the manifest (host/rig/loop/manifest.py) and
    ``make flash`` (host/device/flash.py) alike. The first file on the path wins a board
    path, as an import finds it; the files are :meth:`Firmware.files` (:func:`flash_files`)."""
    placed: dict[str, Path] = {}
    for label, path in firmware.files():
        placed.setdefault(board_name(label), path)
    return placed


HOST_SUFFIXES = (".toml", ".yaml", ".yml", ".md", ".rst", ".pyc", ".pyo", ".pyi", ".log", ".pid", ".lock")
"""Files of these kinds are the host's, never a board's: the tools' configuration in TOML and
YAML (the rig file ``rig.toml``, its ``as_built.toml``, ``pyproject.toml``, ``wokwi.toml``,
Wokwi's test scenarios ``*.test.yaml``, CI files: MicroPython parses neither), documentation
(``README.md``), CPython's bytecode and type stubs, and what host programs leave: logs, pid
and lock files (a rig's external parts run in the rig file's folder, docs/external.md; a
firmware's own log is written on its board)."""
HOST_FILES = (
    "LICENSE.txt",
    "LICENCE.txt",
    "COPYING.txt",
    "requirements.txt",
    "requirements-dev.txt",
    "pytest.ini",
    "tox.ini",
    "setup.cfg",
    "mypy.ini",
    "MANIFEST.in",
)
"""Files by name that are the repository's tools' (pip, pytest and their configuration, the
licence), not the firmware's. (A file with no suffix is a tool's too: ``Makefile``,
``Dockerfile``, ``LICENSE``, a pid file; a library names its data files with their kind.)"""
NOT_FIRMWARE_FOLDERS = ("build", "__pycache__", "tests", "test", "venv", "node_modules", "htmlcov")
"""Folders ``make flash`` never puts on a board (and hidden ones, and trace folders)."""
TRACE_FILES = ("header.json", "trace.jsonl", "manifest.json", "console.log")
"""A folder holding two of these is a run's trace folder (docs/traces.md), not firmware (one
alone may be the firmware's own data: a ``manifest.json`` of its assets)."""


def is_test_file(name: str) -> bool:
    """pytest's files (``test_*.py``, ``*_test.py``, ``conftest.py``): the host's, not the board's."""
    return name.endswith(".py") and (name.startswith("test_") or name.endswith("_test.py") or name == "conftest.py")


def is_host_file(name: str) -> bool:
    """A file of the firmware folder that stays on the host: hidden, pytest's, one of
    :data:`HOST_SUFFIXES` or :data:`HOST_FILES`, one with no suffix, or an editor's backup
    (``main.py~``)."""
    suffix = Path(name).suffix
    return (
        name.startswith(".")
        or is_test_file(name)
        or not suffix
        or suffix in HOST_SUFFIXES
        or name in HOST_FILES
        or name.endswith("~")
    )


def _skipped_folder(path: Path) -> bool:
    name = path.name
    if name.startswith(".") or name in NOT_FIRMWARE_FOLDERS or name.endswith(".egg-info"):
        return True
    return sum((path / marker).exists() or (path / marker).is_symlink() for marker in TRACE_FILES) >= 2


def _takes(name: str) -> bool:
    return not is_host_file(name)


def _refuse(folder: Path, path: Path, what: str):
    from host.core.errors import ConfigError

    return ConfigError(
        f"firmware folder {folder}: {path.relative_to(folder).as_posix()} is {what}; a board's flash "
        "holds only regular files from inside the firmware folder (copy the file in, or move it out "
        "of the folder)"
    )


def flash_files(folder: Path) -> tuple[list[tuple[str, Path]], list[str]]:
    """What ``make flash`` puts on a board from one firmware folder, the one rule of the
    per-run board copy, the manifest and ``make flash`` (host/device/flash.py): every file
    inside it, subfolders too, as ``mpremote cp -r`` copies a folder (code, and the data a
    library reads at run time: images, fonts, text, web pages, blobs), except the host's
    (:func:`is_host_file`: hidden files, pytest's, the rig file and other TOML, documentation,
    the repository's tools' files) and the host's folders (hidden ones, ``build/``,
    ``tests/``, ``__pycache__``, ``venv/``, ``node_modules/``, ``htmlcov/``, ``*.egg-info`` and
    trace folders: a folder with two of ``header.json``, ``trace.jsonl``, ``manifest.json`` and
    ``console.log``).
    A link (to a file or a folder) or a special file where such a file would be taken is
    refused by name (ConfigError), never followed. Returns ([(path in the folder, file)], [its
    subfolders, empty ones too]), sorted."""
    folder = Path(folder).resolve()
    files: list[tuple[str, Path]] = []
    folders: list[str] = []
    if not folder.is_dir():
        return files, folders
    pending = [folder]
    while pending:
        here = pending.pop()
        with os.scandir(here) as entries:
            found = sorted(entries, key=lambda e: e.name)
        for entry in found:
            path = Path(entry.path)
            if entry.is_symlink():
                target = os.readlink(path)
                if entry.name.startswith(".") or entry.name in NOT_FIRMWARE_FOLDERS:
                    continue
                if path.is_dir() or _takes(entry.name):
                    raise _refuse(folder, path, f"a symbolic link (to {target})")
                continue
            if entry.is_dir(follow_symlinks=False):
                if not _skipped_folder(path):
                    folders.append(path.relative_to(folder).as_posix())
                    pending.append(path)
            elif _takes(entry.name):
                if not entry.is_file(follow_symlinks=False):
                    raise _refuse(folder, path, "not a regular file (a FIFO, socket or device)")
                files.append((path.relative_to(folder).as_posix(), path))
    return sorted(files), sorted(folders)


def regular_file(folder: Path, name: str) -> Path | None:
    """``folder/name`` when it is a regular file inside ``folder`` (the entry file), None
    when there is none; a link or a special file there is refused by name."""
    folder = Path(folder).resolve()
    path = folder / name
    if not path.is_relative_to(folder) or ".." in Path(name).parts:
        from host.core.errors import ConfigError

        raise ConfigError(
            f"firmware folder {folder}: an entry {name!r} that leaves it; a board's flash holds only "
            "files from inside the firmware folder (put the entry in it)"
        )
    if path.is_symlink():
        raise _refuse(folder, path, f"a symbolic link (to {os.readlink(path)})")
    if not path.exists():
        return None
    for parent in path.relative_to(folder).parents:
        if (folder / parent).is_symlink():
            raise _refuse(folder, folder / parent, f"a symbolic link (to {os.readlink(folder / parent)})")
    if not path.is_file():
        raise _refuse(folder, path, "not a regular file")
    return path


def _digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


PREFIX = "mpy-fil-board-"


def remove_stale() -> None:
    """Remove the board folders of processes that are gone (killed outright: SIGKILL, an
    OOM kill), named by their pid (``mpy-fil-board-<pid>-…``)."""
    for folder in Path(tempfile.gettempdir()).glob(PREFIX + "*-*"):
        pid = folder.name[len(PREFIX) :].split("-", 1)[0]
        if pid.isdigit() and not Path("/proc", pid).exists():
            shutil.rmtree(folder, ignore_errors=True)


class BoardFs:
    """One run's board folder: made from the firmware, kept in part, removed."""

    def __init__(self, firmware):
        self.flash_bytes = firmware.flash_bytes
        self.faults: list[str] = []  # files past the flash's size (:meth:`written`)
        remove_stale()
        self.root = Path(tempfile.mkdtemp(prefix=f"{PREFIX}{os.getpid()}-"))
        self.flashed: dict[str, str] = {}  # board path: digest of what was flashed
        try:
            for folder in flash_files(firmware.main_dir)[1]:  # (its folders too, empty ones included)
                (self.root / folder).mkdir(parents=True, exist_ok=True)
            placed = on_board(firmware)
            total = sum(path.stat().st_size for path in placed.values())
            if total > self.flash_bytes:
                from host.core.errors import ConfigError

                largest = sorted(placed.items(), key=lambda item: -item[1].stat().st_size)[:3]
                named = ", ".join(f"{name} ({path.stat().st_size} bytes)" for name, path in largest)
                raise ConfigError(
                    f"firmware folder {firmware.main_dir}: its {len(placed)} files take {total} bytes, more than "
                    f"the board's {self.flash_bytes}-byte flash ([board] flash_size) holds: as `make flash` "
                    f"would, the run stops (a bigger flash_size, or fewer files; the largest: {named})"
                )
            for name, path in placed.items():
                dest = self.root / name
                dest.parent.mkdir(parents=True, exist_ok=True)
                shutil.copyfile(path, dest)
                self.flashed[name] = _digest(dest)
        except BaseException:
            self.remove()
            raise

    def written(self) -> list[str]:
        """Board paths of the files the firmware created or changed, sorted: regular files
        only (a link or a special file is never followed or read), at most the flash's size
        read in all; what is past it is named in :attr:`faults` and not read."""
        found, budget = [], self.flash_bytes
        self.faults = []
        for path in self._files():
            name = path.relative_to(self.root).as_posix()
            size = path.lstat().st_size
            if size > budget:
                self.faults.append(
                    f"board_fs/{name}: {size} bytes, more than the {self.flash_bytes}-byte flash holds "
                    "(written round the shim's filesystem): not kept"
                )
                continue
            budget -= size
            if self.flashed.get(name) != _digest(path):
                found.append(name)
        return found

    def _files(self) -> list[Path]:
        out = []
        for folder, dirs, files in os.walk(self.root):  # (links never followed)
            dirs.sort()
            for name in sorted(files):
                path = Path(folder) / name
                if path.is_file() and not path.is_symlink():
                    out.append(path)
        return sorted(out)

    def keep(self, folder: Path) -> list[str]:
        """Copy what the firmware wrote into ``folder`` (made only if there is any)."""
        names = self.written()
        for name in names:  # (board_fs/ or a folder in it a link: refused; a link at a file's name replaced)
            dest = safefs.make_folder((Path(folder) / name).parent, base=Path(folder).parent) / Path(name).name
            with safefs.replacing(dest) as temp:
                shutil.copyfile(self.root / name, temp)
        return names

    def remove(self) -> None:
        shutil.rmtree(self.root, ignore_errors=True)
