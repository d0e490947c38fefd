"""An app: a firmware and its test rig, in memory. Rig files describe one
(:mod:`host.rig.config.rigfile`); the project's own are listed by :mod:`host.rig.config.apps`."""

from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from host.core.paths import FIRMWARE
from host.rig.config.budgets import Budget
from host.rig.scan import boards as pin_maps
from sim_plant.plant import Plant

BOARD_ONLY_MODULES = ("network", "bluetooth", "esp32", "espnow")
"""Modules the ESP32 and RP2040 ports build in (or freeze) and the loop has not."""
PROBE_PREFIX = "probe:"
"""Wiring target prefix for a pin that only the harness watches (a logic-analyser probe)."""


@dataclass
class App:
    """A firmware and its test rig: where the code is, the board, the plant, the wiring,
    the budgets and the worlds. Rig files (``host/rig/config/rigfile.py``) describe one."""

    name: str
    default_board: str
    make_plant: Callable[..., Plant]
    wiring: dict[str, str]
    make_budgets: Callable[[Plant], list[Budget]] = lambda plant: []
    """The app's budgets for a plant: a budget's expected value comes from the plant it
    measures (the sonar period is the plant's ``sonar_period_us``)."""
    boards: tuple[str, ...] = ()
    doc: str = ""
    extra: dict = field(default_factory=dict)
    folder: Path | None = None  # default: firmware/apps/<name>
    worlds: dict[str, dict] = field(default_factory=lambda: {"default": {}})
    """Named worlds: the plant options that build each (the first is the default)."""
    entry: str = "main.py"  # the file the board runs after boot.py
    lib_dirs: tuple[Path, ...] = ()  # library folders of the firmware's own (its /lib)
    harness_lib: bool = True  # the project's firmware/lib on the path
    board_dir: Path | None = None  # the folder of a board file of one's own
    pins: dict | None = None  # the default board's pins, when not read from firmware/boards
    rig_file: Path | None = None
    heap_size: str | None = None  # the interpreter's heap (``-X heapsize``), as a board's
    ticks_wrap_s: float | None = None  # ticks_ms/ticks_us wrap this long into the run (10 s)
    mpy_version: str | None = None  # [interpreter] version: the MicroPython the board runs (docs/versions.md)
    identity: tuple[str, str] | None = None  # (sys.platform, machine): default by board name
    console_max_bytes: int | None = None  # the console file's cap (default: 64 MiB)
    console_baud: int = 115_200  # the REPL UART's baud rate: print() takes its time (0: free)
    cpu: str = "free"  # the board's CPU whose time compute costs ([board] cpu, docs/mcu-time.md)
    allow_exit: bool = False  # the firmware may end by design ([run] allow_exit)

    @property
    def path(self) -> Path:
        return self.folder or FIRMWARE / "apps" / self.name

    def import_hint(self, traceback: str) -> str:
        """A hint for an ImportError of a driver the harness has but this firmware did not
        ask for (``harness_lib``)."""
        import re

        missing = re.search(r"no module named '([\w.]+)'", traceback)
        if missing and missing.group(1) in BOARD_ONLY_MODULES:
            return (
                f"\n({missing.group(1)} is built into a board's MicroPython and not into the loop: "
                "docs/shim.md lists the modules the loop has and how they differ)"
            )
        if missing and not self.harness_lib and (FIRMWARE / "lib" / f"{missing.group(1)}.py").is_file():
            return (
                f"\n(the harness has a driver {missing.group(1)}.py in firmware/lib; a rig file puts "
                "it on the path with [firmware] harness_lib = true)"
            )
        return ""

    def board_files(self, board: str) -> tuple[Path | None, dict]:
        """(the folder with the board's board.py, or None; its pins) for ``board``."""
        if board == self.default_board and self.pins is not None:
            platform = (self.identity or pin_maps.identity(board) or (None,))[0]
            return self.board_dir, pin_maps.with_builtin_lines(self.pins, platform)
        return pin_maps.board_dir(board), pin_maps.read_pin_map(board)

    def firmware_folders(self, board_folder: Path | None) -> list[Path]:
        """Folders as a board's filesystem has them: the app at /, its libraries and the
        pin map in /lib (and the project's drivers, when asked for)."""
        folders = [self.path, *self.lib_dirs]
        if board_folder is not None:
            folders.append(board_folder)
        if self.harness_lib:
            folders.append(FIRMWARE / "lib")
        return folders
