"""An app: a firmware and its test rig, in memory. Rig files describe one
(:mod:`host.rig.config.rigfile`); the project's own are listed by :mod:`host.rig.config.apps`."""

from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from host.core.paths import FIRMWARE
from host.rig.config.budgets import Budget
from host.rig.scan import boards as pin_maps
from host.rig.targets.boardfs import Confinement
from host.rig.targets.firmware import CONSOLE_BAUD, ENTRY
from sim_plant.plant import Plant

BOARD_ONLY_MODULES = ("network", "bluetooth", "esp32", "espnow")
"""Modules the ESP32 and RP2040 ports build in (or freeze) and the loop has not (network: on a
board without a radio)."""
RADIO_MODULES = ("network",)
"""Modules the loop has on a board with a radio only (host/shim/network.py)."""
PROBE_PREFIX = "probe:"
"""Wiring target prefix for a pin that only the harness watches (a logic-analyser probe)."""


@dataclass(frozen=True)
class Code:
    """Where the firmware's code is (``[firmware]``)."""

    folder: Path | None = None  # default: firmware/apps/<name>
    entry: str = ENTRY  # the file the board runs after boot.py
    lib_dirs: tuple[Path, ...] = ()  # library folders of the firmware's own (its /lib)
    harness_lib: bool = True  # the project's firmware/lib on the path
    allow_exit: bool = False  # the firmware may end by design ([firmware] allow_exit)


@dataclass(frozen=True)
class BoardSettings:
    """The board the firmware runs on, beyond its name (``[board]``)."""

    also: tuple[str, ...] = ()  # the boards the rig file names (the default first)
    folder: Path | None = None  # the folder of a board file of one's own
    pins: dict | None = None  # the default board's pins, when not read from firmware/boards
    identity: tuple[str, str] | None = None  # (sys.platform, machine): default by board name
    cpu: str = "free"  # the board's CPU whose time compute costs ([board] cpu, docs/mcu-time.md)
    console_baud: int = CONSOLE_BAUD  # the REPL UART's baud rate: print() takes its time (0: free)
    confine: Confinement = Confinement()
    in_set: str | None = None  # its name among the boards of a rig file with several (docs/multi-board.md)


@dataclass(frozen=True)
class InterpreterSettings:
    """The interpreter the firmware runs on (``[interpreter]``)."""

    heap_size: str | None = None  # the interpreter's heap (``-X heapsize``), as a board's
    ticks_wrap_s: float | None = None  # ticks_ms/ticks_us wrap this long into the run (10 s)
    mpy_version: str | None = None  # [interpreter] version: the MicroPython the board runs (docs/versions.md)


@dataclass(frozen=True)
class Judge:
    """How a campaign's run passes (``[report.judge]``, docs/campaigns.md); None: not asked."""

    console: str | None = None  # a text the console must show
    no_contact: bool | None = None
    home_within_m: float | None = None  # the robot ends this near its start
    min_coverage: float | None = None  # the fraction of the floor covered


@dataclass(frozen=True)
class PoseLine:
    """How the firmware prints its pose (``[report.pose_line]``, docs/traces.md)."""

    tag: str
    columns: tuple[str, ...]  # t, x, y, heading
    m_per_unit: float
    rad_per_unit: float
    probe: str
    what: str


@dataclass(frozen=True)
class Report:
    """The rig file's ``[report]``: its views by name, its pose line, its judge (each None
    when the rig file does not say)."""

    views: tuple[str, ...] | None = None
    pose_line: PoseLine | None = None
    judge: Judge | None = None

    def table(self) -> dict:
        """The table as the rig file gave it, as the trace header keeps it (``report``)."""
        table: dict = {}
        if self.views is not None:
            table["views"] = list(self.views)
        if self.pose_line is not None:
            table["pose_line"] = {**vars(self.pose_line), "columns": list(self.pose_line.columns)}
        if self.judge is not None:
            table["judge"] = {k: v for k, v in vars(self.judge).items() if v is not None}
        return table


@dataclass(frozen=True)
class RunSettings:
    """What a run of the app adds around the firmware: its faults (``[[faults]]``), its
    console file's cap (``[trace]``), its report (``[report]``)."""

    faults: tuple = ()  # sim_plant.faults' specs, injected into every run
    console_max_bytes: int | None = None  # the console file's cap (default: 64 MiB)
    report: Report | None = None


@dataclass
class App:
    """A firmware and its test rig: the board, the plant, the wiring, the budgets and the
    worlds, and by concern where its code is (:class:`Code`), the board's settings
    (:class:`BoardSettings`), the interpreter's (:class:`InterpreterSettings`) and what a
    run adds (:class:`RunSettings`). Rig files (``host/rig/config/rigfile.py``) describe one."""

    name: str
    default_board: str
    make_plant: Callable[..., Plant]
    wiring: dict[str, str]
    make_budgets: Callable[[Plant], list[Budget]] = lambda plant: []
    """The app's budgets for a plant: a budget's expected value comes from the plant it
    measures (the sonar period is the plant's ``sonar_period_us``)."""
    doc: str = ""
    worlds: dict[str, dict] = field(default_factory=lambda: {"default": {}})
    """Named worlds: the plant options that build each (the first is the default)."""
    rig_file: Path | None = None
    code: Code = Code()
    board: BoardSettings = BoardSettings()
    interpreter: InterpreterSettings = InterpreterSettings()
    run: RunSettings = RunSettings()

    @property
    def path(self) -> Path:
        return self.code.folder or FIRMWARE / "apps" / self.name

    def import_hint(self, traceback: str) -> str:
        """A hint for an ImportError of a driver the harness has but this firmware did not
        ask for (``harness_lib``)."""
        import re

        missing = re.search(r"no module named '([\w.]+)'", traceback)
        if missing and missing.group(1) in RADIO_MODULES:
            return (
                f"\n({missing.group(1)} is the radio's: the loop has it on a board with one, an ESP32, a "
                "Pico W or Pico 2 W, an XRP, as their ports build it in; this board has none. docs/shim.md, "
                '"The radio: network and socket")'
            )
        if missing and missing.group(1) in BOARD_ONLY_MODULES:
            return (
                f"\n({missing.group(1)} is built into a board's MicroPython and not into the loop: "
                "docs/shim.md lists the modules the loop has and how they differ)"
            )
        if missing and not self.code.harness_lib and (FIRMWARE / "lib" / f"{missing.group(1)}.py").is_file():
            return (
                f"\n(the harness has a driver {missing.group(1)}.py in firmware/lib; a rig file puts "
                "it on the path with [firmware] harness_lib = true)"
            )
        return ""

    def board_files(self, board: str) -> tuple[Path | None, dict]:
        """(the folder with the board's board.py, or None; its pins) for ``board``."""
        if board == self.default_board and self.board.pins is not None:
            platform = (self.board.identity or pin_maps.identity(board) or (None,))[0]
            return self.board.folder, pin_maps.with_builtin_lines(self.board.pins, platform)
        return pin_maps.board_dir(board), pin_maps.read_pin_map(board)

    def firmware_folders(self, board_folder: Path | None) -> list[Path]:
        """Folders as a board's filesystem has them: the app at /, its libraries and the
        pin map in /lib (and the project's drivers, when asked for)."""
        folders = [self.path, *self.code.lib_dirs]
        if board_folder is not None:
            folders.append(board_folder)
        if self.code.harness_lib:
            folders.append(FIRMWARE / "lib")
        return folders
