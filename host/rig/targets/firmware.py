"""Where a rig's firmware comes from, and the interpreter path that finds it.

A board's filesystem has the app at ``/`` and drivers in ``/lib``; the unix port gets
the same view from ``MICROPYPATH``: the shim first (so ``machine`` and ``time`` are the
harness's), then the firmware's folders, then the frozen modules (``asyncio``).
"""

import hashlib
import os
import re
from dataclasses import dataclass
from pathlib import Path

from host.core.errors import ConfigError
from host.core.interpreter import VERSION_ENV
from host.core.paths import SHIM_DIR
from host.rig.targets import mcutime
from host.rig.targets.boardfs import DEFAULT_FLASH_BYTES, board_name, flash_files, regular_file
from host.rig.targets.heap import SHIM_HEAP_BYTES  # the shim's share: the interpreter gets heap_size plus this

COVERAGE_HEAP_BYTES = 64 * 1024  # the coverage tracer's closures and frames (docs/coverage.md)
# -X heapsize as MicroPython's unix port reads it (strtol, then an optional w and K or M),
# without its octal (a leading 0) and signs
HEAP_SIZE = re.compile(r"([1-9][0-9]*|0[xX][0-9a-fA-F]+)([wW]?)([kKmM]?)")

ENTRY = "main.py"
"""The file a board runs after boot.py when the rig file names no ``[firmware] entry``."""
CONSOLE_BAUD = 115_200
"""The REPL UART's baud rate when the rig file names none (``[board] console_baud``): the
one default (the shim is always told the rate, in WELCOME: :class:`ShimSettings`)."""
TICKS_WRAP_S = 10.0
"""When ticks_ms and ticks_us wrap, in seconds into the run, when the rig file names no
``[interpreter] ticks_wrap_s``."""


@dataclass(frozen=True)
class ShimSettings:
    """What the shim is told of its run in WELCOME (docs/protocol.md, "Settings"): each
    setting once, with its one default here; the shim has none of its own. A target sends
    what fits it (:meth:`host.rig.targets.target.Target.shim_settings`)."""

    entry: str = ENTRY  # the file run after boot.py
    console_baud: int = CONSOLE_BAUD  # print() takes the REPL UART's time (0: free, or a board's own UART)
    ticks_wrap_s: float = TICKS_WRAP_S
    board_fs: str = ""  # the board's folder on the host (host/rig/targets/boardfs.py); "": not confined
    flash_bytes: int = DEFAULT_FLASH_BYTES  # the board's filesystem ([board] flash_size)
    allow: tuple = ()  # host modules the rig file allows ([board] allow_modules)
    heap_bytes: int = 0  # the firmware's heap as it starts (0: the interpreter's whole heap)
    cpu: str = ""  # compute costs this CPU's time (host/rig/targets/mcutime.py; "": free)
    cpu_cost: bytes = b""  # its cost table (mcutime.Cpu.table)
    cpu_heap: int = 0  # the heap its collections are modelled in (mcutime.heap_model)

    def packed(self, identity: tuple[str, str] | None = None) -> dict:
        """The codec's dict (host/shim/_hilframe.py pack_welcome); ``identity``: the board's
        (platform, machine), which becomes the firmware's sys.platform and machine."""
        return {
            "console_baud": self.console_baud,
            "ticks_wrap_ms": int(self.ticks_wrap_s * 1000),
            "flash_bytes": self.flash_bytes,
            "heap_bytes": self.heap_bytes,
            "cpu_heap": self.cpu_heap,
            "identity": ";".join(identity).encode() if identity else b"",
            "entry": self.entry.encode(),
            "board_fs": self.board_fs.encode(),
            "allow": ",".join(self.allow).encode(),
            "cpu": self.cpu.encode(),
            "cpu_cost": self.cpu_cost,
        }


def heap_bytes(size: str | int) -> int | None:
    """Bytes of a ``heap_size`` (``192K``, ``2M``, ``0x30000``, ``24wK``, 262144), or None
    for text the unix port would not read."""
    match = HEAP_SIZE.fullmatch(str(size)) if not isinstance(size, bool) else None
    if not match:
        return None
    number, words, unit = match.groups()
    scale = {"": 1, "k": 1024, "m": 1 << 20}[unit.lower()] * (2 if words else 1)  # w: 8-byte words, per 4 bytes
    return int(number, 0) * scale


@dataclass
class Firmware:
    main_dir: Path  # the folder the entry file runs in (the board's /)
    folders: list[Path]  # on the path, in order: main_dir first
    entry: str = ENTRY
    heap_size: str | None = None  # -X heapsize, as a board's RAM
    ticks_wrap_s: float | None = None  # when ticks_ms/ticks_us wrap (None: TICKS_WRAP_S)
    console_baud: int = CONSOLE_BAUD  # the REPL UART: print() takes its time (0: free)
    flash_bytes: int = DEFAULT_FLASH_BYTES  # the board's filesystem ([board] flash_size)
    allow: tuple = ()  # host modules the rig file allows ([board] allow_modules)
    sandbox: str = "auto"  # the interpreter in namespaces of its own ([board] sandbox, host/rig/targets/sandbox.py)
    board_root: Path | None = None  # this run's copy, the board's / (host/rig/targets/boardfs.py)
    coverage_fd: int | None = None  # the tracer writes here (host/coverage, docs/coverage.md)
    cpu: str = "free"  # compute costs this CPU's time ([board] cpu, host/rig/targets/mcutime.py)
    mpy_version: str | None = None  # [interpreter] version (docs/versions.md)

    @classmethod
    def from_app(cls, app, board_folder: Path | None, main_dir: Path | None = None) -> "Firmware":
        """The app's folder (or ``main_dir``), its libraries, the board's pin map and,
        when the app asks for them, the project's drivers."""
        main = Path(main_dir) if main_dir else app.path
        if regular_file(main, app.code.entry) is None:
            raise ConfigError(f"main_dir: no {app.code.entry} in {main}")
        folders = app.firmware_folders(board_folder)
        confine, interpreter = app.board.confine, app.interpreter
        return cls(
            main,
            [main, *folders[1:]],
            app.code.entry,
            interpreter.heap_size,
            interpreter.ticks_wrap_s,
            app.board.console_baud,
            confine.flash_bytes,
            confine.allow,
            confine.sandbox,
            cpu=app.board.cpu,
            mpy_version=interpreter.mpy_version,
        )

    @classmethod
    def flashed(cls, folder: Path, require_main: bool = True) -> "Firmware":
        """A flashed board folder: main.py, board.mpy, lib/."""
        folder = Path(folder)
        if require_main and regular_file(folder, "main.py") is None:
            raise ConfigError(f"firmware_dir: no main.py in {folder} (flash it first: make flash)")
        return cls(folder, [folder, folder / "lib"])

    def identity(self) -> dict:
        """Which firmware ran: its folder and a hash of every file it can import or read
        on its path (the code, data and board files, packages' ``__init__.py``) and of the
        entry file wherever it lives, so a trace says what it is the trace of."""
        digest = hashlib.sha256()
        files = self.files()
        for label, path in files:
            digest.update(f"{label}\0".encode() + path.read_bytes())
        return {
            "folder": str(self.main_dir),
            "entry": self.entry,
            "files": len(files),
            "sha256": digest.hexdigest()[:16],
        }

    def files(self) -> list[tuple[str, Path]]:
        """The files :meth:`identity` hashes, each once, with the label it is hashed under
        (its place on the path: the folder's index and the path within it): the entry first.
        What each folder gives is what ``make flash`` puts on a board (:func:`flash_files`:
        no tests, no ``build/``, no trace folders; a link is refused by name)."""
        found, seen = [], set()
        entry = regular_file(self.main_dir, self.entry)
        if entry is not None:
            found.append((f"entry:{self.entry}", entry))
            seen.add(entry)
        for index, folder in enumerate(self.folders):
            for rel, path in flash_files(folder)[0]:
                if path not in seen:
                    seen.add(path)
                    found.append((f"{index}:{rel}", path))
        return found

    def board_files(self) -> list[tuple[str, Path]]:
        """:meth:`files`, each with its path on the board (``main.py``, ``lib/motor.py``)
        instead of its label."""
        return [(board_name(label), path) for label, path in self.files()]

    def micropypath(self, shim: bool | Path = True) -> str:
        """The interpreter's path: the shim's folder (``shim``: the one given, or the source
        folder for True: host/core/shimcache.py), then the board's."""
        board = [self.board_root, self.board_root / "lib"] if self.board_root else self.folders
        folders = [SHIM_DIR if shim is True else shim, *board] if shim else board
        return ":".join([*map(str, folders), ".frozen"])

    def shim_settings(self) -> ShimSettings:
        """What the shim is told in WELCOME when it runs here, in the unix port: the entry,
        the console's rate, the ticks' wrap, the board's folder and flash size, the host
        modules allowed, the firmware's heap and the CPU whose time compute costs."""
        given = {"ticks_wrap_s": self.ticks_wrap_s} if self.ticks_wrap_s is not None else {}
        board = {"board_fs": str(self.board_root), "flash_bytes": self.flash_bytes} if self.board_root else {}
        heap = {"heap_bytes": self.firmware_heap_bytes()} if self.heap_size else {}
        # compute's cost on the board's CPU (MPYFIL_CPU overrides the rig file's, docs/mcu-time.md)
        cpu = mcutime.shim_settings(os.environ.get("MPYFIL_CPU") or self.cpu, self.rig_heap_bytes())
        return ShimSettings(
            entry=self.entry, console_baud=self.console_baud, allow=tuple(self.allow), **given, **board, **heap, **cpu
        )

    def env(self, link_path: str, shim: Path = SHIM_DIR) -> dict:
        """The interpreter's environment: what must be there before the link opens (the
        settings come in WELCOME, :meth:`shim_settings`). The path (the shim from
        ``shim``, which finds the shim itself), the pty the shim opens (HIL_LINK: it names
        the link), the file descriptor the coverage tracer writes to (HIL_COVERAGE_FD: this
        process's own, given at its start) and HIL_PURE (the host's switch, passed on)."""
        return {
            "PATH": os.environ.get("PATH", "/usr/bin:/bin"),
            "MICROPYPATH": self.micropypath(shim),
            "HIL_LINK": link_path,
            **({"HIL_COVERAGE_FD": str(self.coverage_fd)} if self.coverage_fd is not None else {}),
            # the shim's pure-Python hot path even where the build has it in C (host/shim/cmod)
            **({"HIL_PURE": "1"} if os.environ.get("HIL_PURE") else {}),
        }

    def micropython(self) -> str | None:
        """The MicroPython version this run asks for: ``$MPY_FIL_MICROPYTHON`` (``pytest
        --mpy-version``) over the rig file's ``[interpreter] version``; None: the default."""
        return os.environ.get(VERSION_ENV) or self.mpy_version

    def rig_heap_bytes(self) -> int | None:
        """The rig file's heap_size in bytes (the firmware's heap as on its board), or None."""
        return heap_bytes(self.heap_size) if self.heap_size else None

    def firmware_heap_bytes(self) -> int:
        """The heap the firmware finds free as it starts (the shim takes the rest: _hilboot)."""
        return heap_bytes(self.heap_size) + (COVERAGE_HEAP_BYTES if self.coverage_fd is not None else 0)

    def interpreter_args(self) -> list[str]:
        if not self.heap_size:
            return []
        # The shim's share: its start-up runs beside the firmware's heap, set apart first
        # (host/shim/_hilboot.py), under the coverage tracer too when it is on.
        shim = SHIM_HEAP_BYTES + (COVERAGE_HEAP_BYTES if self.coverage_fd is not None else 0)
        pool = self.firmware_heap_bytes() + shim
        # py/gc.c's gc_init keeps its tables in the heap it is given (2 bits a 16-byte block
        # for allocation, 1 for finalisers: 3/128 of it), so the pool is that much smaller
        # than -X heapsize: the share must not shrink as heap_size grows
        return ["-X", f"heapsize={pool * 128 // 125 + 1}"]
