"""Where a run comes from: the harness's commit (a checkout's; an installed harness is named
by its version) and, apart from it, the commit of the user's repository the rig file is in,
for trace headers, manifests and reports."""

import functools
import subprocess
from pathlib import Path

from host.core.paths import CHECKOUT, REPO, project_root

GIT_TIMEOUT_S = 5.0


@functools.cache
def commit() -> str:
    """The harness's checked-out commit, with ``-dirty`` when tracked files differ from it,
    or ``unknown`` when the harness is not a git checkout of its own (installed from a wheel:
    a repository around the installation is the user's, never the harness's)."""
    if not CHECKOUT or _git(REPO, "rev-parse", "--show-toplevel") != str(REPO):
        return "unknown"
    return _commit_of(REPO) or "unknown"


@functools.cache
def project_commit(folder: Path) -> dict | None:
    """The user's repository ``folder`` (a rig file's folder) is in, apart from the
    harness's: ``{"root", "commit"}`` (``commit`` None when the root is not a git checkout);
    None when ``folder`` is in no repository or is the harness's own checkout."""
    root = project_root(folder)
    if root is None or (CHECKOUT and root == REPO):
        return None
    top = _git(root, "rev-parse", "--show-toplevel")
    return {"root": str(root), "commit": _commit_of(root) if top and Path(top) == root else None}


def _commit_of(folder: Path) -> str | None:
    try:
        head = _git(folder, "rev-parse", "HEAD")
        dirty = _git(folder, "status", "--porcelain", "--untracked-files=no")
    except (OSError, subprocess.SubprocessError):
        return None
    return head + ("-dirty" if dirty else "") if head else None


def _git(folder: Path, *args: str) -> str:
    try:
        done = subprocess.run(
            ["git", "-C", str(folder), *args], capture_output=True, text=True, timeout=GIT_TIMEOUT_S, check=False
        )
    except (OSError, subprocess.SubprocessError):
        return ""
    return done.stdout.strip() if done.returncode == 0 else ""
