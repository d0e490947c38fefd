"""What a test session does when it is told to stop: nothing it started outlives it.

SIGTERM (a CI timeout; ``make`` passes its own on to the recipe) and SIGHUP (the terminal
closed) stop the session as Ctrl-C does: a ``KeyboardInterrupt`` in the running test, so
its fixtures stop its rigs and virtual boards and pytest reports what ran. A second such
signal ends the session at once. Under pytest-xdist the controller passes the signal on to
its workers, and each worker gets SIGTERM from the kernel when the controller ends, however
it ends (SIGKILL included). Whatever is left to the kernel: a rig's interpreter and a
virtual board's server have a parent-death signal of their own (:mod:`host.core.children`).
"""

import os
import signal
import sys
import threading
from pathlib import Path

import pytest

from host.core.children import die_with_parent

SIGNALS = (signal.SIGTERM, signal.SIGHUP)
PLUGIN = "hil-stopping"


def install(config, worker: bool) -> None:
    """Called from ``pytest_configure``: the handlers (unless the process has its own), and
    a worker's parent-death signal."""
    if worker:
        die_with_parent(signal.SIGTERM)  # (xdist forks its workers from the controller's main thread)
    if not config.pluginmanager.has_plugin(PLUGIN):
        config.pluginmanager.register(sys.modules[__name__], PLUGIN)
    if threading.current_thread() is not threading.main_thread():
        return
    forward = not worker and bool(getattr(config.option, "numprocesses", None))
    for sig in SIGNALS:
        if signal.getsignal(sig) is signal.SIG_DFL:
            signal.signal(sig, _Stop(forward))


class _Stop:
    """The handler: the first signal interrupts the session, the next ends it."""

    def __init__(self, forward: bool):
        self.forward = forward

    def __call__(self, signum, _frame):
        for sig in SIGNALS:
            signal.signal(sig, signal.SIG_DFL)
        if self.forward:  # the xdist workers: each interrupts its own test
            for pid in children(os.getpid()):
                try:
                    os.kill(pid, signum)
                except ProcessLookupError:
                    pass
        raise SessionStopped(f"test session stopped by {signal.Signals(signum).name}")


class SessionStopped(KeyboardInterrupt):
    """Raised by the handler where the signal found the session: pytest reports it as an
    interrupt."""


@pytest.hookimpl(tryfirst=True)
def pytest_keyboard_interrupt(excinfo):
    """A stop by signal is reported by its one line, not by where it found the session (pytest
    would read and parse the source of every frame: seconds on a loaded machine). Any other
    interrupt: frames with no line number (Python 3.11 has some, in the rig's hot loop) make
    pytest's report of it fail with a TypeError, so they are left out."""
    if isinstance(excinfo.value, SessionStopped):
        excinfo.traceback = excinfo.traceback[-1:]
    else:
        excinfo.traceback = excinfo.traceback.filter(lambda entry: getattr(entry._rawentry, "tb_lineno", 0) is not None)


def children(pid: int) -> list[int]:
    """The processes whose parent is ``pid`` (from /proc)."""
    found = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except (OSError, IndexError):
            continue  # ended while listed
        if int(fields[1]) == pid:
            found.append(int(stat.parent.name))
    return found
