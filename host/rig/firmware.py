"""Where a rig's firmware comes from, and the interpreter path that finds it.

A board's filesystem has the app at ``/`` and drivers in ``/lib``; the unix port gets
the same view from ``MICROPYPATH``: the shim first (so ``machine`` and ``time`` are the
harness's), then the firmware's folders, then the frozen modules (``asyncio``).
"""

import os
from dataclasses import dataclass
from pathlib import Path

from host.core.errors import ConfigError
from host.core.paths import FIRMWARE, SHIM_DIR


@dataclass
class Firmware:
    main_dir: Path  # the folder main.py runs in (the board's /)
    folders: list[Path]  # on the path, in order: main_dir first

    @classmethod
    def from_source(cls, app_dir: Path, board_dir: Path, main_dir: Path | None = None) -> "Firmware":
        """The app's folder (or ``main_dir``), the board's pin map, the drivers."""
        main = Path(main_dir) if main_dir else Path(app_dir)
        if not (main / "main.py").is_file():
            raise ConfigError(f"main_dir: no main.py in {main}")
        return cls(main, [main, Path(board_dir), FIRMWARE / "lib"])

    @classmethod
    def flashed(cls, folder: Path, require_main: bool = True) -> "Firmware":
        """A flashed board folder: main.py, board.mpy, lib/."""
        folder = Path(folder)
        if require_main and not (folder / "main.py").is_file():
            raise ConfigError(f"firmware_dir: no main.py in {folder} (flash it first: make flash)")
        return cls(folder, [folder, folder / "lib"])

    def micropypath(self, shim: bool = True) -> str:
        folders = [SHIM_DIR, *self.folders] if shim else self.folders
        return ":".join([*map(str, folders), ".frozen"])

    def env(self, link_path: str) -> dict:
        """The interpreter's environment: the path, and the pty the shim opens."""
        return {
            "PATH": os.environ.get("PATH", "/usr/bin:/bin"),
            "MICROPYPATH": self.micropypath(),
            "HIL_LINK": link_path,
        }
