"""TOML as text, for the files the harness writes (``mpy-fil import-wokwi``'s rig,
``mpy-fil migrate``'s): one value, one key. (``tomllib`` reads TOML; nothing in the
standard library writes it.)"""

import json
import re

BARE_KEY = re.compile(r"[A-Za-z0-9_-]+")


def value(v) -> str:
    """One TOML value: text, true/false, a number, a list, an inline table."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):  # (a JSON string is a TOML basic string, but for DEL, which TOML escapes)
        return json.dumps(v).replace("\x7f", "\\u007f")
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(value(i) for i in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{key(k)} = {value(i)}" for k, i in v.items()) + " }"
    raise TypeError(f"no TOML for {v!r}")


def key(k: str) -> str:
    """A key: bare when TOML allows it, else quoted."""
    return k if BARE_KEY.fullmatch(k) else value(k)
