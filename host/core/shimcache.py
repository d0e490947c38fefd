"""The shim compiled once: its modules as ``.mpy`` files made by the ``mpy-cross`` of the
interpreter's own build, so a run does not parse and compile the shim's 7,000 lines at
every start (three quarters of a rig's start-up instructions, docs/bench.md).

The compiled folder is keyed by what makes its bytes: the compiler's version line, the
native architecture, each shim file's name and content. It is made once, in a temporary
folder renamed into place (two workers that make it at once both get a whole folder), under
the build folder beside the interpreters (a checkout's ``build/shim/``, or the per-user
cache's). Each module is compiled with its source name in the compiled folder
(``mpy-cross -s``), so the shim's folder is one place for everything that asks
(``__file__``, the exempt folder of MCU time, the coverage tracer, the sandbox's view).

An interpreter that is not one of our builds (a user's own, ``$MICROPYTHON``), or no
matching compiler, gives the shim's source folder: compiled at each start, as before.
``MPY_FIL_SHIM_SOURCE=1`` asks for the source folder always (a shim edited while tests
run is compiled by each run then: nothing is cached)."""

import functools
import hashlib
import os
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

from host.core import interpreter, paths

SOURCE_ENV = "MPY_FIL_SHIM_SOURCE"
ARCHS = {1: "x86", 2: "x64", 3: "armv6", 4: "armv6m", 5: "armv7m", 6: "armv7em", 7: "armv7emsp", 8: "armv7emdp"}
"""``sys.implementation._mpy``'s architecture field (bits 10 and up, py/persistentcode.h)
as mpy-cross's ``-march`` names it."""


def folder(program: str | Path) -> Path:
    """The folder the shim is loaded from for the interpreter ``program``: its compiled
    folder when one can be made, else the shim's source folder (:data:`paths.SHIM_DIR`)."""
    if os.environ.get(SOURCE_ENV, "").strip() not in ("", "0"):
        return paths.SHIM_DIR
    target = Path(program)
    try:
        mtime = target.stat().st_mtime_ns
    except OSError:
        return paths.SHIM_DIR
    made = _compiled(str(target), mtime, _sources_stamp(), cache_root())
    return made or paths.SHIM_DIR


def cache_root() -> Path:
    """Where compiled folders are kept: ``shim/`` beside the interpreters' build folder."""
    return interpreter.build_root().parent / "shim"


def _sources() -> list[Path]:
    return sorted(paths.SHIM_DIR.glob("*.py"))


def _sources_stamp() -> tuple:
    """What says the shim's files changed (their names, sizes and times), for the cache of
    :func:`_compiled` in this process; the folder's key is their content."""
    return tuple((p.name, st.st_size, st.st_mtime_ns) for p in _sources() for st in [p.stat()])


@functools.cache
def _compiled(program: str, _mtime_ns: int, _stamp: tuple, root: Path) -> Path | None:
    about = _interpreter(program)
    if about is None:
        return None
    line, mpy = about
    compiler = _compiler(line)
    if compiler is None:
        return None
    arch = ARCHS.get(mpy >> 10)
    key = hashlib.sha256(f"{line}\n{arch}\n".encode())
    sources = _sources()
    for path in sources:
        key.update(path.name.encode() + b"\0" + path.read_bytes() + b"\0")
    final = root / key.hexdigest()[:16]
    if (final / "_hilboot.mpy").is_file():
        return final
    root.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=".making-", dir=root))
    try:
        for path in sources:
            if not _compile(compiler, arch, path, final / path.name, tmp / f"{path.stem}.mpy"):
                shutil.copyfile(path, tmp / path.name)  # (what this compiler refuses is loaded as source)
        try:
            os.rename(tmp, final)
        except OSError:  # (another process made it first: its folder is the same)
            if not (final / "_hilboot.mpy").is_file():
                return None
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    _prune(root, keep=final)
    return final


STALE_S = 7 * 24 * 3600
"""A compiled folder made this long ago goes when a new one is made (a shim edited often
leaves one a version; a run still loading from one that old is not expected)."""


def _prune(root: Path, keep: Path) -> None:
    now = time.time()
    for folder in root.iterdir():
        try:
            old = folder != keep and now - folder.stat().st_mtime > STALE_S
        except OSError:
            continue
        if old:
            shutil.rmtree(folder, ignore_errors=True)


def _compile(compiler: Path, arch: str | None, source: Path, named: Path, out: Path) -> bool:
    cmd = [str(compiler), *([f"-march={arch}"] if arch else []), "-s", str(named), "-o", str(out), str(source)]
    done = subprocess.run(cmd, capture_output=True, timeout=60)
    return done.returncode == 0 and out.is_file()


def _interpreter(program: str) -> tuple[str, int] | None:
    """The interpreter's version line (``MicroPython v1.25.0+ds-1 on 2025-05-04``) and its
    ``sys.implementation._mpy``; None when it does not say them."""
    try:
        out = subprocess.run(
            [program, "-c", "import sys; print(sys.version.split('; ')[-1]); print(sys.implementation._mpy)"],
            capture_output=True,
            text=True,
            timeout=10,
        )
        line, mpy = out.stdout.split("\n")[:2]
        return line.strip(), int(mpy)
    except (OSError, ValueError, subprocess.SubprocessError):
        return None


def _compiler(line: str) -> Path | None:
    """The mpy-cross built from the same source as the interpreter (its version line the same,
    up to "; mpy-cross emitting ..."), from the build folders' source trees."""
    for root in dict.fromkeys((interpreter.build_root(), interpreter.build_root(checkout=False))):
        for candidate in sorted(root.glob("src*/micropython-*/mpy-cross/build/mpy-cross")):
            if _compiler_line(str(candidate)) == line:
                return candidate
    return None


@functools.cache
def _compiler_line(path: str) -> str | None:
    try:
        out = subprocess.run([path, "--version"], capture_output=True, text=True, timeout=10)
    except (OSError, subprocess.SubprocessError):
        return None
    return out.stdout.split(";")[0].strip() or None
