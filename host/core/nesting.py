"""Nesting bombs in what the user hands the harness: ``[`` a hundred thousand times in a
diagram, a scenario, a rig file or a trace folder's JSON. Each parser the harness uses
(``json``, ``tomllib``, PyYAML) is recursive and meets such a file with a RecursionError
(PyYAML after seconds); each reader asks :func:`too_deep` where the nesting passes
:data:`MAX_DEPTH` and names it (``nested deeper than 64 levels at line 1, column 65``)
in its own typed error, before or instead of the parser's crash.
"""

import json
from pathlib import Path

MAX_DEPTH = 64
"""Lists and tables within each other that any file the harness reads needs at most."""


def too_deep(text, limit: int = MAX_DEPTH, quotes: str = "\"'") -> str | None:
    """Where ``text`` (JSON, TOML or YAML flow style: brackets and braces, strings in
    ``quotes`` skipped) first nests deeper than ``limit``: ``"nested deeper than N levels
    at line L, column C"``; None when it never does. Linear in the text, no recursion."""
    if isinstance(text, (bytes, bytearray)):
        text = bytes(text).decode("utf-8", errors="replace")
    depth, line, start, quote, escaped = 0, 1, 0, "", False
    for i, char in enumerate(text):
        if char == "\n":
            line, start = line + 1, i + 1
        if quote:
            if escaped:
                escaped = False
            elif char == "\\" and quote == '"':
                escaped = True
            elif char == quote or char == "\n":
                quote = ""
        elif char in quotes:
            quote = char
        elif char in "[{":
            depth += 1
            if depth > limit:
                return f"nested deeper than {limit} levels at line {line}, column {i - start + 1}"
        elif char in "]}":
            depth = max(depth - 1, 0)
    return None


def loads_json(text, where: str):
    """``text`` as JSON; a ConfigError naming ``where`` (a file, a line of one) when it is
    not JSON or nests past what the parser reads (where it does)."""
    from host.core.errors import ConfigError

    try:
        return json.loads(text)
    except RecursionError:
        raise ConfigError(f"{where}: not JSON that can be read: {too_deep(text) or 'nested too deep'}") from None
    except ValueError as e:  # (UnicodeDecodeError is one)
        raise ConfigError(f"{where}: not JSON: {e}") from None


def read_json(path, what: str = "file"):
    """The JSON in ``path`` (a ``what``); a ConfigError naming it when it cannot be read."""
    from host.core.errors import ConfigError

    try:
        text = Path(path).read_bytes()
    except OSError as e:
        raise ConfigError(f"{path}: cannot read the {what} ({e.strerror or e})") from None
    return loads_json(text, str(path))
