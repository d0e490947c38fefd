"""The interpreter in a sandbox of its own: Linux namespaces through bubblewrap (``bwrap``).

Defence in depth under the shim's confinement (docs/security.md): the unix port runs with
no network (a network namespace of its own), no other user's or process's view (user, IPC
and UTS namespaces), and a filesystem that holds only the interpreter and the libraries it
links, the shim (read-only), the run's board folder (the only thing it can write) and,
under ``/dev``, ``null``, ``urandom`` and the link's pty. Nothing else of the host's
filesystem is there: no ``/etc``, no home, no ``/tmp``, no sources.

Where the kernel refuses (a container without user namespaces) or ``bwrap`` is missing,
the run goes on with the shim's confinement, unless the sandbox is required:
``[board] sandbox = "require"`` in the rig file or ``MPY_FIL_SANDBOX=require`` in the
environment (``off`` turns it off, ``auto`` is the default). How loudly it says so depends
on whose firmware it is (:func:`received`): for a folder in the user's own repository, a
note; for any other (a folder received, downloaded, or a third party's), a warning block
on stderr (and a ``SandboxWarning`` under pytest), since a firmware written to get round
the shim's confinement then reaches this machine. Either way the manifest records it
(:func:`record`: ``sandbox`` in ``manifest.json``). No PID namespace: the harness signals
the interpreter itself (its stack on a hang), found as bwrap's child.
"""

import functools
import os
import re
import shutil
import subprocess
import sys
import warnings
from pathlib import Path

from host.core.children import popen_options
from host.core.errors import SetupError
from host.core.paths import BUNDLED, REPO, SHIM_DIR

ENV = "MPY_FIL_SANDBOX"
CHOICES = ("auto", "require", "off")
PROBE_TIMEOUT_S = 10.0
_said: set = set()  # the notes and warnings given in this process (a note once, a warning once a folder)
_records: dict = {}  # board folder -> how its interpreter ran (record())
_RECORDS_KEPT = 64


class SandboxWarning(UserWarning):
    """A firmware from outside the user's own repository ran without the sandbox."""


def setting(rig_setting: str = "auto") -> str:
    """The environment's choice over the rig file's (a CI machine may require it)."""
    value = os.environ.get(ENV, "").strip() or rig_setting
    if value not in CHOICES:
        raise SetupError(f"{ENV}={value!r}: expected one of {', '.join(CHOICES)}")
    return value


@functools.cache
def libraries(program: str) -> tuple[str, ...]:
    """The shared objects ``program`` links (ldd), and the dynamic loader."""
    try:
        out = subprocess.run(["ldd", program], capture_output=True, text=True, timeout=10, **popen_options()).stdout
    except (OSError, subprocess.TimeoutExpired):
        return ()
    found = re.findall(r"(/\S+\.so[.\d]*)", out)
    return tuple(dict.fromkeys(found))


@functools.cache
def refusal() -> str | None:
    """Why this machine runs no sandbox (None: it does)."""
    bwrap = shutil.which("bwrap")
    if bwrap is None:
        return "bubblewrap (bwrap) is not installed: `make setup` installs it as root, or apt-get install bubblewrap"
    try:
        done = subprocess.run(
            [bwrap, "--ro-bind", "/", "/", "--unshare-user", "--unshare-net", "--", "true"],
            capture_output=True,
            text=True,
            timeout=PROBE_TIMEOUT_S,
            **popen_options(),
        )
    except (OSError, subprocess.TimeoutExpired) as e:
        return f"bwrap does not run: {e}"
    if done.returncode != 0:
        return f"the kernel refuses new namespaces ({done.stderr.strip() or done.returncode})"
    return None


def _work_tree(path: Path) -> Path | None:
    """The git work tree ``path`` is in (a folder holding ``.git``), or None."""
    for folder in (path, *path.parents):
        if (folder / ".git").exists():
            return folder
    return None


def received(folder: Path | None, cwd: Path | None = None) -> bool:
    """Whether a firmware folder is someone else's: neither in the harness's own files
    (its examples and firmware) nor in the git work tree the command runs in (``cwd``'s:
    the user's own repository). A folder in no work tree, a download, a clone beside one's
    own repository, a folder someone sent are received (docs/security.md)."""
    if folder is None:
        return False
    folder = Path(folder).resolve()
    if folder.is_relative_to(REPO.resolve()) or folder.is_relative_to(BUNDLED.resolve()):
        return False
    own = _work_tree(Path(cwd or Path.cwd()).resolve())
    return own is None or not folder.is_relative_to(own)


def record(board_root: Path | None) -> dict:
    """How the interpreter of the run on ``board_root`` was confined, for its manifest:
    the setting, whether the sandbox ran, why not, and whether the firmware was received."""
    found = _records.get(str(board_root)) if board_root is not None else None
    return found or {"setting": "off", "running": False, "why": "no per-run board folder", "received": False}


def _keep(board_root: Path, entry: dict) -> None:
    _records[str(board_root)] = entry
    while len(_records) > _RECORDS_KEPT:
        _records.pop(next(iter(_records)))


def command(
    argv: list[str],
    board_root: Path | None,
    link_path: str,
    wanted: str,
    source: Path | None = None,
    shim: Path = SHIM_DIR,
) -> list[str]:
    """``argv`` inside the sandbox, or as it is when the sandbox is off or refused (a
    SetupError when it is required and refused). ``source``: the firmware's folder (whose
    firmware it is decides how loudly a refused sandbox is told: :func:`received`)."""
    if board_root is None:
        return argv
    foreign = received(source)
    if wanted == "off":
        _keep(
            board_root,
            {"setting": wanted, "running": False, "why": f"{ENV} or [board] sandbox is off", "received": foreign},
        )
        return argv
    why = refusal() or _not_elf(argv[0])
    if why is not None:
        if wanted == "require":
            by = f"{ENV}=require" if os.environ.get(ENV, "").strip() else '[board] sandbox = "require" in the rig file'
            raise SetupError(
                f"the sandbox is required ({by}) but {why}: the firmware in {source or board_root} "
                "was not started (docs/security.md)"
            )
        _keep(board_root, {"setting": wanted, "running": False, "why": why, "received": foreign})
        if foreign:
            _warn(why, source)
        else:
            _note(why)
        return argv
    _keep(board_root, {"setting": wanted, "running": True, "why": None, "received": foreign})
    program = str(Path(argv[0]).resolve())
    view = ["--tmpfs", "/", "--dir", "/tmp"]  # (an empty root: only what is bound below)
    for path in (*libraries(program), program):
        real = str(Path(path).resolve())
        view += ["--ro-bind", real, real]
        if real != path:
            view += ["--symlink", real, path]
    view += ["--ro-bind", str(shim), str(shim), "--bind", str(board_root), str(board_root)]
    view += ["--dev-bind", "/dev/null", "/dev/null", "--dev-bind", "/dev/urandom", "/dev/urandom"]
    view += ["--dev-bind", link_path, link_path, "--remount-ro", "/"]
    spaces = ["--unshare-user", "--unshare-ipc", "--unshare-net", "--unshare-uts", "--unshare-cgroup-try"]
    return [
        shutil.which("bwrap"),
        *spaces,
        "--die-with-parent",
        *view,
        "--chdir",
        str(board_root),
        "--",
        program,
        *argv[1:],
    ]


def _not_elf(program: str) -> str | None:
    """Why ``program`` cannot run alone in the sandbox (a script needs its interpreter;
    a file the kernel does not run is left to fail as it does outside)."""
    try:
        with open(program, "rb") as f:
            if f.read(4) == b"\x7fELF":
                return None
    except OSError:
        pass
    return f"{program} is not an ELF program"


def _note(why: str) -> None:
    if "note" not in _said:
        _said.add("note")
        print(
            f"mpy-fil: note: the firmware runs without a sandbox here ({why}); the shim still confines it "
            f"(docs/security.md; {ENV}=require to refuse such runs)",
            file=sys.stderr,
        )


def warning_text(why: str, source: Path | None) -> str:
    """The warning block for a received firmware that runs without the sandbox."""
    rule = "mpy-fil: WARNING " + "=" * 62
    return "\n".join(
        [
            rule,
            f"mpy-fil: WARNING: the firmware in {source} runs WITHOUT the sandbox: {why}.",
            "mpy-fil: WARNING: it is not in your own repository (nor one of the harness's examples): only the",
            "mpy-fil: WARNING: shim confines it, and a firmware written to get round the shim reaches this",
            "mpy-fil: WARNING: machine as you: your files, your network, your processes (docs/security.md).",
            "mpy-fil: WARNING: install bubblewrap (`make setup`, or apt-get install bubblewrap) where user",
            f"mpy-fil: WARNING: namespaces are allowed; refuse such runs with {ENV}=require or",
            f'mpy-fil: WARNING: [board] sandbox = "require"; {ENV}=off says you trust it.',
            "mpy-fil: WARNING: manifest.json records how it ran (sandbox).",
            rule,
        ]
    )


def _warn(why: str, source: Path | None) -> None:
    key = f"warning {source}"
    if key in _said:
        return
    _said.add(key)
    text = warning_text(why, source)
    print(text, file=sys.stderr)
    if "_pytest" in sys.modules:  # (pytest keeps a passing test's stderr: its warnings summary shows this)
        warnings.warn(SandboxWarning(text), stacklevel=3)


def interpreter_pid(proc: subprocess.Popen) -> int:
    """The interpreter's own pid: bwrap's child when sandboxed, else the process's."""
    if Path(proc.args[0]).name != "bwrap":
        return proc.pid
    try:
        children = Path(f"/proc/{proc.pid}/task/{proc.pid}/children").read_text().split()
    except OSError:
        return proc.pid
    return int(children[0]) if children else proc.pid
