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


def confinement(where, board) -> dict:
    """The ``[board]`` settings of the firmware's confinement, for ``App.extra``."""
    board = board if isinstance(board, dict) else {}
    return {
        "flash_bytes": flash_bytes(where, board),
        "allow": allowed_modules(where, board),
        "sandbox": sandbox_setting(where, board),
    }


def board_name(label: str) -> str:
    """Where a file of :meth:`Firmware.files` lies on the board: the first folder's
    (and the entry) at /, the others' in /lib."""
    where, _, rel = label.partition(":")
    return rel if where in ("entry", "0") else f"lib/{rel}"


def _folders(main: Path) -> list[str]:
    """The firmware folder's own subfolders (not hidden, not ``__pycache__``), relative."""
    found = []
    for path in sorted(main.rglob("*")) if main.is_dir() else ():
        parts = path.relative_to(main).parts
        if path.is_dir() and not any(p.startswith(".") or p == "__pycache__" for p in parts):
            found.append(path.relative_to(main).as_posix())
    return found


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
        remove_stale()
        self.root = Path(tempfile.mkdtemp(prefix=f"{PREFIX}{os.getpid()}-"))
        self.flashed: dict[str, str] = {}  # board path: digest of what was flashed
        try:
            for folder in _folders(Path(firmware.main_dir)):  # (its folders too, empty ones included)
                (self.root / folder).mkdir(parents=True, exist_ok=True)
            for label, path in firmware.files():
                name = board_name(label)
                if name in self.flashed:
                    continue  # (the first on the path wins, as imports find it)
                dest = self.root / name
                dest.parent.mkdir(parents=True, exist_ok=True)
                shutil.copyfile(path, dest)
                self.flashed[name] = _digest(dest)
        except BaseException:
            self.remove()
            raise

    def written(self) -> list[str]:
        """Board paths of the files the firmware created or changed, sorted."""
        found = []
        for path in sorted(self.root.rglob("*")):
            if path.is_file() and not path.is_symlink():
                name = path.relative_to(self.root).as_posix()
                if self.flashed.get(name) != _digest(path):
                    found.append(name)
        return found

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
