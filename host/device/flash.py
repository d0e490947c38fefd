"""``make flash``: put an app on a board the way it was tested.

1. Compile the app's modules, the board's pin map and the drivers with mpy-cross for
   the target's .mpy version (``main.py`` and ``boot.py`` stay source, as boards run
   them); a syntax error stops the flash and names file and line. The firmware folder's
   data files (images, fonts, text, web pages: all but the host's, boardfs.is_host_file)
   go as they are.
2. Copy them with mpremote, which skips every file whose content the board already
   has (SHA-256 on the board); remove a stale ``.py`` where a ``.mpy`` now stands.
3. Soft-reset the board in its friendly REPL, so ``main.py`` runs, and show the first
   lines it prints.

Without ``--port`` the target is the virtual board of ``host/device/vboard.py`` (its folder
``build/vboard/<board>/fs`` keeps what was flashed; ``make hil FIRMWARE=<folder>`` runs
the HIL scenarios from exactly those files).
"""

import argparse
import contextlib
import fcntl
import json
import os
import re
import shutil
import signal
import stat
import subprocess
import sys
import time
from pathlib import Path

from host.core.children import popen_options
from host.core.errors import HarnessError
from host.core.paths import REPO
from host.device import vboard
from host.rig.config.apps import apps, get_app
from host.rig.targets.boardfs import on_board
from host.rig.targets.firmware import Firmware

STAGING = REPO / "build" / "flash"
VENV_BIN = Path(sys.executable).parent
MPREMOTE_TIMEOUT_S = 120
FIRST_LINE_S = 15.0
"""After a reset, how long to wait for a board's first line when none came within ``--wait``."""


class FlashError(HarnessError):
    pass


def _tool(name: str) -> str:
    path = VENV_BIN / name
    if path.exists():
        return str(path)
    found = shutil.which(name)
    if not found:
        raise FlashError(f"{name} not found: run `make setup`")
    return found


def mpy_cross_version() -> tuple[int, int]:
    cmd = [_tool("mpy-cross"), "--version"]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True, **popen_options()).stdout
    m = re.search(r"mpy v(\d+)\.(\d+)", out)
    if not m:
        raise FlashError(f"cannot read the .mpy version from `mpy-cross --version`: {out.strip()}")
    return int(m.group(1)), int(m.group(2))


def compile_module(src: Path, dst: Path) -> None:
    """mpy-cross one file; a syntax error becomes 'file:line: message'."""
    rel = os.path.relpath(src, REPO)
    dst.parent.mkdir(parents=True, exist_ok=True)
    cmd = [_tool("mpy-cross"), "-s", src.name, "-o", str(dst), str(src)]
    out = subprocess.run(cmd, capture_output=True, text=True, **popen_options())
    if out.returncode != 0:
        text = out.stderr + out.stdout
        line = re.search(r"line (\d+)", text)
        last = [t for t in text.strip().splitlines() if t.strip()][-1:] or ["mpy-cross failed"]
        raise FlashError(f"{rel}:{line.group(1) if line else '?'}: {last[0].strip()}")


def stage(app_name: str, board: str, root: Path | None = None) -> tuple[Path, list[str]]:
    """Build the board's filesystem image in build/flash/<app>-<board>/ (or under
    ``root``); return the folder and the files in it (relative paths, as on the board)."""
    app = get_app(app_name)
    out = Path(root or STAGING) / f"{app.name}-{board}"
    if out.exists():
        shutil.rmtree(out)
    out.mkdir(parents=True)
    files: list[str] = []
    board_folder, _pins = app.board_files(board)
    for name, src in on_board(Firmware.from_app(app, board_folder)).items():  # (host/rig/targets/boardfs.py)
        if name in ("main.py", "boot.py", app.code.entry) or not name.endswith(".py"):
            if name.endswith(".py"):
                compile_module(src, out.parent / ".check" / name.replace(".py", ".mpy"))  # syntax check only
            (out / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(src, out / name)
            files.append(name)
        else:
            mpy = name[:-3] + ".mpy"
            compile_module(src, out / mpy)
            files.append(mpy)
    return out, files


def check_port(port: str) -> None:
    try:
        mode = os.stat(port).st_mode
    except OSError:
        raise FlashError(f"PORT={port}: no such serial port (is the board plugged in?)") from None
    if not stat.S_ISCHR(mode):
        raise FlashError(f"PORT={port}: not a serial device")


class _Interrupt:
    """Ctrl-C while flashing: the CLI's SIGINT handler ends the running mpremote at
    once and the flash stops at the next step, so no mpremote is left on the port."""

    def __init__(self):
        self.hit = False
        self.proc = None

    def handler(self, _signum, _frame):
        self.hit = True
        if self.proc is not None and self.proc.poll() is None:
            self.proc.kill()

    def check(self):
        if self.hit:
            raise KeyboardInterrupt


_interrupt = _Interrupt()


def _mpremote(port: str, *args: str) -> str:
    """Run mpremote in its own session (a terminal's Ctrl-C reaches only this tool), killed
    if this process ends first."""
    cmd = [_tool("mpremote"), "connect", port, *args]
    _interrupt.check()
    proc = subprocess.Popen(
        cmd, cwd=str(REPO), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, **popen_options()
    )
    _interrupt.proc = proc
    try:
        _interrupt.check()
        out, _ = proc.communicate(timeout=MPREMOTE_TIMEOUT_S)
    finally:
        _interrupt.proc = None
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    _interrupt.check()
    if proc.returncode != 0:
        lines = [t for t in out.strip().splitlines() if t.strip()] or ["(no output)"]
        said = "".join(f"\n  {t[-300:]}" for t in lines[-6:-1])  # (what the board sent: mpremote prints it)
        raise FlashError(
            f"PORT={port}: mpremote {' '.join(args)[:80]} failed: {lines[-1]}" + (f"; before it:{said}" if said else "")
        )
    return out


MPY_PROBE = "import sys\nprint('MPY', getattr(sys.implementation, '_mpy', -1))"
"""What a board runs to say the .mpy version it loads (:func:`mpy_of` reads the answer)."""


def mpy_of(out: str) -> tuple[int, int] | None:
    """The (version, sub-version) of .mpy in what :data:`MPY_PROBE` printed; None if it said none."""
    m = re.search(r"MPY (-?\d+)", out)
    value = int(m.group(1)) if m else -1
    return None if value < 0 else (value & 0xFF, (value >> 8) & 3)


def target_mpy_version(port: str) -> tuple[int, int]:
    out = _mpremote(port, "exec", MPY_PROBE)
    version = mpy_of(out)
    if version is None:
        raise FlashError(f"PORT={port}: the board did not report its .mpy version: {out.strip()[-200:]}")
    return version


def copy(port: str, folder: Path, files: list[str]) -> tuple[list[str], list[str]]:
    """Copy what changed; return (copied, unchanged)."""
    root = [str(folder / f) for f in files if "/" not in f]
    args = ["cp", *root, ":"]
    for top in sorted({f.split("/", 1)[0] for f in files if "/" in f}):  # /lib and the app's own folders
        args += ["+", "cp", "-r", str(folder / top), ":"]
    stale = [f[:-4] + ".py" for f in files if f.endswith(".mpy")]
    args += ["+", "exec", "import os\nfor f in %r:\n try:\n  os.remove(f)\n except OSError:\n  pass" % stale]
    out = _mpremote(port, *args)
    unchanged = sorted(m.group(1).lstrip("/") for m in re.finditer(r"Up to date: (?:\./)?(\S+)", out))
    copied = sorted(f for f in files if f not in unchanged)
    return copied, unchanged


def reset_and_read(port: str, max_lines: int = 10, wait_s: float = 3.0) -> list[str]:
    """Soft-reset in the friendly REPL (main.py runs) and return the first lines."""
    import serial

    with serial.Serial(port, 115200, timeout=0.1) as ser:
        ser.write(b"\r\x03")  # stop what runs
        _read_until(ser, b">>> ", 3.0)
        ser.write(b"\x02")  # friendly REPL
        _read_until(ser, b">>> ", 3.0)
        _read_quiet(ser, 0.3)
        ser.write(b"\x04")  # soft reset: boot.py, main.py
        data = _read_until(ser, None, wait_s, max_lines + 1)
        deadline = time.monotonic() + max(0.0, FIRST_LINE_S - wait_s)
        while not _lines(data[: data.rfind(b"\n") + 1]) and time.monotonic() < deadline:
            data += ser.read(256)  # a board slow to boot (a loaded host): wait for its first whole line
    return _lines(data)[:max_lines]


def _lines(data: bytes) -> list[str]:
    text = data.decode(errors="replace").replace("\r\n", "\n")
    return [t for t in text.split("\n") if t.strip() and "soft reboot" not in t]


def _read_quiet(ser, quiet_s: float, timeout_s: float = 3.0) -> None:
    """Read until nothing more arrives for quiet_s (the board has settled at its prompt)."""
    deadline = time.monotonic() + timeout_s
    last = time.monotonic()
    while time.monotonic() < deadline and time.monotonic() - last < quiet_s:
        if ser.read(256):
            last = time.monotonic()


def _read_until(ser, marker: bytes | None, timeout_s: float, max_lines: int = 0) -> bytes:
    data = b""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        data += ser.read(256)
        if marker is not None and data.endswith(marker):
            break
        if max_lines and data.count(b"\n") > max_lines:
            break
    return data


def flash(
    app: str, board: str | None = None, port: str | None = None, *, lines: int = 10, wait_s: float = 3.0, log=print
) -> dict:
    board = board or get_app(app).default_board
    with staging_lock(app, board):  # (two flashes of one app and board at once take turns)
        return _flash(app, board, port, lines=lines, wait_s=wait_s, log=log)


@contextlib.contextmanager
def staging_lock(app: str, board: str):
    """Hold the staging folder of one app and board while it is built and copied: a second
    ``make flash`` (or a test) of the same app waits instead of rebuilding the folder
    under the first one's copy."""
    STAGING.mkdir(parents=True, exist_ok=True)
    with open(STAGING / f".{get_app(app).name}-{board}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        yield


def _flash(app: str, board: str, port: str | None, *, lines: int, wait_s: float, log) -> dict:
    folder, files = stage(app, board)
    ours = None
    if port is None:
        if vboard.running_port(board) is None:
            ours = board
        port = vboard.start_background(board, app=app)
        where = f"virtual board {board} on {port} (folder {vboard.board_home(board) / 'fs'})"
    else:
        check_port(port)
        where = port
    try:
        log(f"flash {app} for {board} -> {where}")
        want, have = mpy_cross_version(), target_mpy_version(port)
        if want != have:
            raise FlashError(
                f"PORT={port}: the board runs .mpy v{have[0]}.{have[1]}, mpy-cross emits "
                f"v{want[0]}.{want[1]}: pin mpy-cross to the board's MicroPython version"
            )
        log(f"  compiled {sum(f.endswith('.mpy') for f in files)} modules with mpy-cross (.mpy v{want[0]}.{want[1]})")
        copied, unchanged = copy(port, folder, files)
        log(f"  copied {len(copied)} file(s){': ' + ', '.join(copied) if copied else ''}; {len(unchanged)} up to date")
        if ours or port == vboard.running_port(board):  # what this virtual board now holds
            manifest = {"app": _app_id(app), "board": board, "files": files}
            (vboard.board_home(board) / "flashed.json").write_text(json.dumps(manifest, indent=1))
        _interrupt.check()
        first = reset_and_read(port, lines, wait_s)
        log("  reset; first lines:")
        for line in first:
            log(f"  | {line}")
        return {"port": port, "copied": copied, "unchanged": unchanged, "first_lines": first}
    finally:
        if ours:
            vboard.stop_background(ours)


def _app_id(app: str) -> str:
    """What flashed.json calls the app: our app's name, or its rig file's whole path
    (``make hil FIRMWARE=`` runs the tests of that app from wherever they are)."""
    path = Path(app)
    if app in apps() or not path.exists():
        return app
    return str((path / "rig.toml" if path.is_dir() else path).resolve())


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m host.device.flash", description=__doc__.split("\n")[0])
    parser.add_argument("--app", required=True, help="app folder under firmware/apps")
    parser.add_argument("--board", help="board pin map under firmware/boards (default: the app's)")
    parser.add_argument("--port", help="serial port of the board (default: the virtual board)")
    parser.add_argument("--lines", type=int, default=10, help="how many lines of the board's output to show")
    parser.add_argument("--wait", type=float, default=3.0, help="seconds to wait for them")
    args = parser.parse_args(argv)
    signal.signal(signal.SIGINT, _interrupt.handler)
    try:
        flash(args.app, args.board, args.port or None, lines=args.lines, wait_s=args.wait)
    except HarnessError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("flash interrupted: the board is left at its REPL; flash again to finish", file=sys.stderr)
        return 130
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
