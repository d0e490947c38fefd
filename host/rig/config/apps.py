"""The apps the harness knows: ours, each a rig file beside its firmware
(``firmware/apps/<app>/rig*.toml``), and any rig file named by its path."""

from pathlib import Path

from host.core.errors import ConfigError
from host.core.paths import FIRMWARE
from host.rig.config.app import App
from host.rig.config.rigfile import load_rig

__all__ = ["App", "apps", "get_app"]
_APPS: dict[str, App] = {}


def apps() -> dict[str, App]:
    """Our apps by name, read from their rig files on first use."""
    if not _APPS:
        for path in sorted(FIRMWARE.glob("apps/*/rig*.toml")):
            app = load_rig(path)
            _APPS[app.name] = app
    return _APPS


BOARD_OF_SET = "::"
"""``rig.toml::left``: the board ``left`` of a rig file with several boards, as the trace
folder of that board names it (a replay of one board of a set: docs/multi-board.md)."""


def board_of_set(path: str, board: str) -> App:
    """Board ``board`` of the rig file with several boards at ``path``, as the one-board app
    it amounts to (its inputs, as a trace recorded them, stand for the other boards)."""
    from host.rig.config.boardfile import load_boards

    apps_of_set = load_boards(path).apps
    app = apps_of_set.get(board)
    if not isinstance(app, App):
        known = ", ".join(b for b, a in apps_of_set.items() if isinstance(a, App))
        raise ConfigError(f"app: {path} has no board with firmware named {board!r} (its boards: {known})")
    return app


WHAT_FOLDERS_HOLD = ("rig.toml", "diagram.json")  # a folder named alone: a rig file's, a Wokwi project's


def get_app(name: str) -> App:
    """One of our apps by name, a rig file by its path (``path/to/rig.toml``), or a Wokwi
    project by its folder or its ``diagram.json`` (without a rig.toml: ``docs/wokwi.md``)."""
    if any(ord(c) < 32 or 127 <= ord(c) < 160 for c in name):
        raise ConfigError(f"app: expected an app's name or a rig file's path, got {name!r} (a control character)")
    if BOARD_OF_SET in name:  # one board of a rig file with several (docs/multi-board.md): its trace's header
        return board_of_set(*name.rsplit(BOARD_OF_SET, 1))
    try:
        if name.endswith((".toml", ".json")) or "/" in name or any(Path(name, f).is_file() for f in WHAT_FOLDERS_HOLD):
            path = Path(name)
            from host.rig.config.wokwi.project import is_project, rig_from_project

            if is_project(path):  # a Wokwi project: its diagram.json (docs/wokwi.md)
                return rig_from_project(path)
            return load_rig(path / "rig.toml" if path.is_dir() else path)  # a folder: its rig.toml
    except OSError as e:  # (a name too long for the file system, a folder that cannot be listed)
        raise ConfigError(f"app: cannot read {name[:80]!r}: {e.strerror or e}") from None
    try:
        return apps()[name]
    except KeyError:
        raise ConfigError(
            f"app: unknown app {name!r} (known: {', '.join(sorted(apps()))}; or a rig file's path)"
        ) from None
