"""Where a run comes from: the harness's commit, for trace headers and reports."""

import functools
import subprocess

from host.core.paths import REPO

GIT_TIMEOUT_S = 5.0


@functools.cache
def commit() -> str:
    """The checked-out commit, with ``-dirty`` when tracked files differ from it, or
    ``unknown`` outside a git checkout."""
    try:
        head = _git("rev-parse", "HEAD")
        dirty = _git("status", "--porcelain", "--untracked-files=no")
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    if not head:
        return "unknown"
    return head + ("-dirty" if dirty else "")


def _git(*args: str) -> str:
    done = subprocess.run(
        ["git", "-C", str(REPO), *args], capture_output=True, text=True, timeout=GIT_TIMEOUT_S, check=False
    )
    return done.stdout.strip() if done.returncode == 0 else ""
