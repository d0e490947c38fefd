"""How a firmware run ends, and the errors that say so. Each stops the rig first and
names the virtual time, the seed, the console's last lines and the artefacts
(``Rig.where``): a traceback, an exit the test did not expect, a reboot storm, a damaged
link. ``docs/reliability.md`` lists them with the tests that show them."""

import re
from pathlib import Path

from host.core.errors import FirmwareError, FirmwareExited, FirmwareHung, LinkDamaged, LinkError
from host.core.paths import SHIM_DIR
from host.core.printable import printable
from host.link import frames as F
from host.rig.hardware.bustrace import failed_hint

STORM_RESETS = 10
STORM_RUN_US = 60_000_000
"""A reboot storm: STORM_RESETS resets in a row, each less than STORM_RUN_US of virtual
time after the boot before it (the firmware never ran a minute without resetting), at any
rate, from a reset at boot to one every 59 s. A board that resets less often (a watchdog
every few minutes) is let be. Each reset costs a process start (about 10 ms of wall time),
so a storm ends within a second or two of wall time whatever its rate."""
SHIM_LINK_DAMAGED = "LinkDamaged:"  # the shim's exception, last line of its traceback
CONSOLE_TAIL_LINES = 20
SYNTAX_ERROR = re.compile(r'File "([^"]+)", line (\d+)\s*\n(SyntaxError|IndentationError): ?(.*)\s*$')
"""A traceback that ends in a file the interpreter could not compile (no ``in <function>``)."""
DEEPSLEEP_WAKE = 1
"""EXIT_RESET's code when the board wakes from machine.deepsleep() (no crash: no storm)."""


TRACEBACK = "Traceback (most recent call last):"
FRAME = re.compile(r'  File "([^"]*)"')
SHIM_FILES = frozenset(path.name for path in SHIM_DIR.glob("*.py"))


def shim_frame(path: str) -> bool:
    """A traceback frame of the shim's own code: in its folder (``host/shim``, or its
    compiled copy ``build/shim/<key>/``), in ``/_hil/`` where the sandbox shows it, asyncio's
    task queue (C on a board), or a private module of the shim under its bare name (a board
    in the loop: ``host/device/pil.py`` compiles the shim so)."""
    if path.startswith("/_hil/") or path == "asyncio/task.py":
        return True
    name = Path(path).name
    if name not in SHIM_FILES:
        return False
    if "/" not in path:
        return name.startswith("_hil")
    return Path(path).parent == SHIM_DIR or Path(path).parent.parent.name == "shim"


def board_traceback(text: str) -> str:
    """A firmware's traceback as its board prints it (docs/shim.md, "Tracebacks as on a
    board"): the shim's frames left out. The shim leaves them out itself (host/shim/_hilboot.py,
    ``_board_traceback``) but for a KeyboardInterrupt, whose whole stack the watchdog reads
    (host/rig/targets/target.py, ``diagnosis``); this serves that one when it ends a run
    otherwise (the firmware raised it) and a board in the loop. One whose every frame is
    the shim's is the harness's own failure: kept whole."""
    lines = text.split("\n")
    if lines[0] != TRACEBACK:
        return text
    end = 1
    while end < len(lines) and FRAME.match(lines[end]):
        end += 1
    kept = [line for line in lines[1:end] if not shim_frame(FRAME.match(line).group(1))]
    return "\n".join([TRACEBACK, *kept, *lines[end:]]) if kept else text


def where(rig) -> str:
    """The console's last lines, the seed and the artefacts folder, for error messages."""
    tail = printable("\n".join(rig.console.rstrip().splitlines()[-CONSOLE_TAIL_LINES:]))
    console = f"\nconsole (last {CONSOLE_TAIL_LINES} lines):\n{tail}" if tail else "\nconsole: (empty)"
    trace = getattr(rig, "bus_trace", None)
    for t_us, text in trace.notes if trace is not None else ():
        console += printable(f"\nnote at virtual t={t_us / 1e6:.6f} s: {text}")
    return console + f"\nseed: {rig.seed}" + (f"\nartefacts: {rig.artefacts}" if rig.artefacts else "")


def fault(rig, t: int, text: str):
    """The firmware raised (FAULT): its traceback, whole, ends the run."""
    try:
        rig.session.recv(1.0, "EXIT")  # let the process finish writing
    except (LinkError, FirmwareError, FirmwareHung):
        pass
    rig.stop()
    text = board_traceback(text)
    last = text.rstrip().splitlines()[-1] if text.strip() else ""
    if last.startswith(SHIM_LINK_DAMAGED):
        raise LinkDamaged(
            f"{printable(last[len(SHIM_LINK_DAMAGED) :].strip())} (seen by the shim at virtual t={t / 1e6:.6f} s)"
            f"{rig.where()}"
        )
    syntax = SYNTAX_ERROR.search(text)
    if syntax:  # the board would not run the file at all: one error, where, and the console once
        path, line, kind, message = syntax.groups()
        if not path.startswith("/"):  # (the firmware runs in its folder)
            path = str(rig.firmware.main_dir / path)
        raise FirmwareError(
            f"{kind.lower().replace('error', ' error')} in {printable(path)}, line {line}: {printable(message)} "
            f"(the firmware did not start; found at virtual t={t / 1e6:.6f} s){rig.where()}",
            traceback=text,
            console=rig.console,
        )
    raise FirmwareError(
        f"firmware raised at virtual t={t / 1e6:.6f} s; expected it to keep running.\n"
        f"MicroPython traceback:\n{printable(text.rstrip())}{printable(rig.app.import_hint(text))}"
        f"{failed_hint(getattr(rig, 'bus_trace', None), text)}{rig.where()}",
        traceback=text,
        console=rig.console,
    )


def exited(rig, t: int, kind: int, code: int) -> None:
    """The entry file returned or called sys.exit: a failure unless the rig expects it."""
    if rig.allow_exit:
        return
    how = "its entry file returned" if kind == F.EXIT_RETURN else f"it called sys.exit({code})"
    rig.stop()
    raise FirmwareExited(
        f"the firmware ended at virtual t={t / 1e6:.6f} s ({how}, exit code {code}); expected it to keep "
        f"running (a test that expects the end makes its rig with allow_exit=True).{rig.where()}",
        code=code,
        console=rig.console,
    )


class ResetWatch:
    """The resets of one run, for the storm check: the current run of short boots."""

    def __init__(self, t_start_us: int = 0):
        self.boot_us = t_start_us  # when the running boot began
        self.streak = 0  # boots in a row that reset within STORM_RUN_US of starting
        self.streak_from_us = t_start_us  # when the first of them began
        self.longest_us = 0  # the longest of them

    def seen(self, t_us: int) -> bool:
        """A reset at ``t_us``; True when it makes a storm."""
        ran_us = t_us - self.boot_us
        if ran_us < STORM_RUN_US:
            if not self.streak:
                self.streak_from_us, self.longest_us = self.boot_us, 0
            self.streak += 1
            self.longest_us = max(self.longest_us, ran_us)
        else:  # the firmware ran long enough: this reset is no storm's
            self.streak = 0
        self.boot_us = t_us
        return self.streak >= STORM_RESETS

    def describe(self, t_us: int) -> str:
        span_us = t_us - self.streak_from_us
        if span_us <= 0:
            return f"{self.streak} times at one instant of virtual time (t={t_us / 1e6:.6f} s)"
        rate = self.streak / (span_us / 1e6)
        longest_s = self.longest_us / 1e6
        return (
            f"{self.streak} times in {span_us / 1e6:.6g} s of virtual time ({rate:.3g} resets per virtual second, "
            f"from t={self.streak_from_us / 1e6:.6f} s; the longest run between two resets {longest_s:.6g} s)"
        )


def reset(rig, t: int) -> None:
    """machine.reset() (or a watchdog): stop a board that does little but reset, at any rate."""
    watch = rig.reset_watch
    if watch.seen(t):
        rig.stop()
        raise FirmwareError(
            f"reboot storm: the firmware reset {watch.describe(t)}, never running {STORM_RUN_US / 1e6:g} s of "
            f"virtual time without a reset; expected it to run (a board that resets less often, a watchdog every "
            f"few minutes, is let be).{rig.where()}",
            console=rig.console,
        )


def damaged(rig, error: LinkDamaged):
    """A frame from the firmware was damaged or lost: nothing after it can be trusted."""
    rig.stop()
    raise LinkDamaged(f"{error} (at virtual t={rig.clock.firmware_us / 1e6:.6f} s){rig.where()}") from None
