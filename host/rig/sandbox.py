"""The interpreter in a sandbox of its own: Linux namespaces through bubblewrap (``bwrap``).

Defence in depth under the shim's confinement (docs/security.md): the unix port runs with
no network (a network namespace of its own), no other user's or process's view (user, IPC
and UTS namespaces), and a filesystem that holds only the interpreter and the libraries it
links, the shim (read-only), the run's board folder (the only thing it can write) and,
under ``/dev``, ``null``, ``urandom`` and the link's pty. Nothing else of the host's
filesystem is there: no ``/etc``, no home, no ``/tmp``, no sources.

Where the kernel refuses (a container without user namespaces) or ``bwrap`` is missing,
the run says so once on stderr and goes on with the shim's confinement, unless the
sandbox is required: ``[board] sandbox = "require"`` in the rig file or
``MPY_FIL_SANDBOX=require`` in the environment (``off`` turns it off, ``auto`` is the
default). No PID namespace: the harness signals the interpreter itself (its stack on a
hang), found as bwrap's child.
"""

import functools
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

from host.core.children import popen_options
from host.core.errors import SetupError
from host.core.paths import SHIM_DIR

ENV = "MPY_FIL_SANDBOX"
CHOICES = ("auto", "require", "off")
PROBE_TIMEOUT_S = 10.0
_said = False  # the "no sandbox here" note goes out once per process


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


def command(argv: list[str], board_root: Path | None, link_path: str, wanted: str) -> list[str]:
    """``argv`` inside the sandbox, or as it is when the sandbox is off or refused (a
    SetupError when it is required and refused)."""
    if wanted == "off" or board_root is None:
        return argv
    why = refusal() or _not_elf(argv[0])
    if why is not None:
        if wanted == "require":
            raise SetupError(f"the sandbox is required ({ENV} or [board] sandbox) but {why}")
        _note(why)
        return argv
    program = str(Path(argv[0]).resolve())
    view = ["--tmpfs", "/", "--dir", "/tmp"]  # (an empty root: only what is bound below)
    for path in (*libraries(program), program):
        real = str(Path(path).resolve())
        view += ["--ro-bind", real, real]
        if real != path:
            view += ["--symlink", real, path]
    view += ["--ro-bind", str(SHIM_DIR), str(SHIM_DIR), "--bind", str(board_root), str(board_root)]
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
    global _said
    if not _said:
        _said = True
        print(
            f"mpy-fil: note: the firmware runs without a sandbox here ({why}); the shim still confines it "
            f"(docs/security.md; {ENV}=require to refuse such runs)",
            file=sys.stderr,
        )


def interpreter_pid(proc: subprocess.Popen) -> int:
    """The interpreter's own pid: bwrap's child when sandboxed, else the process's."""
    if Path(proc.args[0]).name != "bwrap":
        return proc.pid
    try:
        children = Path(f"/proc/{proc.pid}/task/{proc.pid}/children").read_text().split()
    except OSError:
        return proc.pid
    return int(children[0]) if children else proc.pid
