"""Checks of the values a rig is given (API and CLI alike): each bad one is a
ConfigError that names the field, what it expected and what it got."""

import math
import secrets

from host.core.errors import ConfigError

SEED_MAX = 2**32 - 1
MAX_RUN_S = 10 * 24 * 3600  # ten simulated days in one run_for (and one `mpy-fil run`)


def seed(value) -> int:
    """A seed of 0 .. 2**32-1; None draws one (the rig records and prints it)."""
    if value is None:
        return secrets.randbelow(SEED_MAX + 1)
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= SEED_MAX:
        raise ConfigError(f"seed: expected an integer 0..{SEED_MAX} (or None to draw one), got {value!r}")
    return value


def seconds(field: str, value, *, positive: bool = False, limit_s: float = math.inf) -> float:
    """A finite number of seconds, >= 0 (> 0 when ``positive``), at most ``limit_s``."""
    ok = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
    if ok and (value > 0 if positive else value >= 0) and value <= limit_s:
        return float(value)
    bound = "> 0" if positive else ">= 0"
    upto = f" and at most {limit_s:g}" if math.isfinite(limit_s) else ""
    raise ConfigError(f"{field}: expected a number of seconds {bound}{upto}, got {value!r}")
