"""Reading a TOML file the user wrote (a rig file, a campaign file, a fault set): any way
it cannot be read (missing, too large, not UTF-8, malformed, nested past the parser) is a
:class:`~host.core.errors.ConfigError` naming the file, in one line."""

from pathlib import Path

import tomllib

from host.core.errors import ConfigError
from host.core.nesting import too_deep

NESTED_DEPTH = 8  # tables and lists within each other that a file of ours needs at most


def read_toml(path: Path, what: str = "file", max_bytes: int | None = None) -> dict:
    """The TOML of ``path`` (a ``what``: "rig file", "file"), at most ``max_bytes`` long."""
    try:
        if not path.is_file():
            raise ConfigError(f"{path}: no such {what}")
        raw = path.read_bytes()
        if max_bytes is not None and len(raw) > max_bytes:
            raise ConfigError(f"{path}: expected a {what} of at most {max_bytes} bytes, got {len(raw)}")
        text = raw.decode("utf-8")
        return tomllib.loads(text)
    except OSError as e:
        raise ConfigError(f"{path}: cannot read the {what} ({e.strerror or e})") from None
    except UnicodeDecodeError as e:
        raise ConfigError(f"{path}: not UTF-8 text (byte {e.object[e.start]:#04x} at offset {e.start})") from None
    except tomllib.TOMLDecodeError as e:
        raise ConfigError(f"{path}: not valid TOML: {e}") from None
    except RecursionError:
        raise ConfigError(f"{path}: not valid TOML: {too_deep(text, NESTED_DEPTH) or 'nested too deep'}") from None
