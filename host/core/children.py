"""Child processes that do not outlive the command that started them.

Every process the harness starts (the unix port, the virtual board's server, a campaign's
pool workers) gets a parent-death signal: when the process that started it ends, however it
ends (an exception, SIGTERM from a CI timeout, SIGKILL), the kernel sends the child SIGKILL.
A child also starts its own session (``start_new_session=True``) so that a terminal's
Ctrl-C reaches the harness, which then stops its children in order; the parent-death signal
is what covers the cases where the harness gets no chance to.

Linux only (``prctl(PR_SET_PDEATHSIG)``); elsewhere :func:`die_with_parent` does nothing.
The signal is tied to the thread that started the child: start children from a thread
that lives as long as they should (the main thread, or a pool's own).
"""

import ctypes
import ctypes.util
import functools
import os
import signal
import sys

PR_SET_PDEATHSIG = 1

_libc = None
if sys.platform.startswith("linux"):
    try:
        _libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
    except OSError:  # pragma: no cover - a libc that cannot be loaded
        _libc = None


def die_with_parent(sig: int = signal.SIGKILL) -> None:
    """Ask the kernel to send ``sig`` to this process when its parent ends. For
    ``preexec_fn`` of :class:`subprocess.Popen` and a pool's initializer. If the parent
    already ended (the race between fork and this call), end now."""
    if _libc is None:
        return
    parent = os.getppid()
    _libc.prctl(PR_SET_PDEATHSIG, int(sig), 0, 0, 0)
    if os.getppid() != parent:
        os.kill(os.getpid(), sig)


def popen_options(sig: int = signal.SIGKILL) -> dict:
    """The :class:`subprocess.Popen` keyword arguments for a child of the harness: its own
    session, and ``sig`` (SIGKILL unless said) when the harness ends. A child that cleans up
    after itself (the virtual board's server removes its pid and port files and stops its
    interpreter) takes SIGTERM; what it starts has SIGKILL from it in turn."""
    preexec = die_with_parent if sig == signal.SIGKILL else functools.partial(die_with_parent, sig)
    return {"start_new_session": True, "preexec_fn": preexec}
