"""The apps the harness knows: ours, each a rig file beside its firmware
(``firmware/apps/<app>/rig*.toml``), and any rig file named by its path."""

from pathlib import Path

from host.core.errors import ConfigError
from host.core.paths import FIRMWARE
from host.rig.app import App
from host.rig.rigfile import load_rig

__all__ = ["App", "apps", "get_app"]
_APPS: dict[str, App] = {}


def apps() -> dict[str, App]:
    """Our apps by name, read from their rig files on first use."""
    if not _APPS:
        for path in sorted(FIRMWARE.glob("apps/*/rig*.toml")):
            app = load_rig(path)
            _APPS[app.name] = app
    return _APPS


def get_app(name: str) -> App:
    """One of our apps by name, or a rig file by its path (``path/to/rig.toml``)."""
    if any(ord(c) < 32 or 127 <= ord(c) < 160 for c in name):
        raise ConfigError(f"app: expected an app's name or a rig file's path, got {name!r} (a control character)")
    try:
        if name.endswith(".toml") or "/" in name or Path(name, "rig.toml").is_file():
            path = Path(name)
            return load_rig(path / "rig.toml" if path.is_dir() else path)  # a folder: its rig.toml
    except OSError as e:  # (a name too long for the file system, a folder that cannot be listed)
        raise ConfigError(f"app: cannot read {name[:80]!r}: {e.strerror or e}") from None
    try:
        return apps()[name]
    except KeyError:
        raise ConfigError(
            f"app: unknown app {name!r} (known: {', '.join(sorted(apps()))}; or a rig file's path)"
        ) from None
