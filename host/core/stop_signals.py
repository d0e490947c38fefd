"""The stop signals of the ``mpy-fil`` command: SIGINT (Ctrl-C), SIGTERM (a CI timeout,
``kill``) and SIGHUP (the terminal closed) stop a command as Ctrl-C does, each reported as
itself with exit code 128 + its number (``host/cli.py``'s main says which).

Imported first by ``host/cli.py``: when that module is the program (the ``mpy-fil`` script,
or ``python -m host.cli``) and not a module a test or a tool imports, the handlers are in
place before its imports, which take a second, and a stop signal during them is one line,
``mpy-fil: stopped by SIGTERM``, not a traceback (or, for SIGTERM, no word at all). A
signal the program was started ignoring (nohup, a shell's background job) stays ignored.
"""

import os
import signal
import sys

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


class Stopped(KeyboardInterrupt):
    """A signal asked the run to stop (raised by the command line's handler)."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum
        self.signal_name = signal.Signals(signum).name


def stop(signum, _frame):
    """A stop signal, as the command's first: the others are ignored from now on (what is
    being written is written, what was started is stopped), and the command stops as at
    Ctrl-C, the signal named (:class:`Stopped`)."""
    for s in STOP_SIGNALS:
        signal.signal(s, signal.SIG_IGN)
    raise Stopped(signum)


def install() -> dict:
    """``stop`` for every stop signal not ignored; the handlers before, to put back."""
    previous = {s: signal.getsignal(s) for s in STOP_SIGNALS}
    for s, handler in previous.items():
        if handler is not signal.SIG_IGN:
            signal.signal(s, stop)
    return previous


def _stopped_uncaught(kind, value, traceback) -> None:
    """sys.excepthook of the program: a stop signal main cannot catch (during the imports,
    before main runs) is one line and its exit code, not a traceback."""
    if not issubclass(kind, KeyboardInterrupt):
        return sys.__excepthook__(kind, value, traceback)
    signum = getattr(value, "signum", signal.SIGINT)
    sys.stdout.flush()
    sys.stderr.write(f"mpy-fil: stopped by {signal.Signals(signum).name}\n")
    sys.stderr.flush()
    os._exit(128 + signum)


def _stopped_unraisable(unraisable) -> None:
    """sys.unraisablehook of the program: a stop signal whose :class:`Stopped` was raised where
    Python cannot raise (a weakref callback such as the import lock's, a ``__del__``) would be
    printed as "Exception ignored" and lost, and the command would go on. Delivered again
    instead, a millisecond later (a timer's SIGALRM), at the next line that can raise, as the
    first would have."""
    value = unraisable.exc_value
    if not isinstance(value, Stopped):
        return sys.__unraisablehook__(unraisable)

    def again(_signum, frame):
        signal.signal(signal.SIGALRM, signal.SIG_DFL)
        stop(value.signum, frame)

    signal.signal(signal.SIGALRM, again)  # (raised here, in the hook, it would be lost again)
    signal.setitimer(signal.ITIMER_REAL, 0.001)


def _the_program() -> bool:
    """host.cli runs as the program: the mpy-fil script, or python -m host.cli (and not a
    campaign's pool worker, which imports the script again as ``__mp_main__``)."""
    main = sys.modules.get("__main__")
    if getattr(main, "__name__", None) == "__mp_main__":
        return False
    spec = getattr(main, "__spec__", None)
    cli = __package__.rpartition(".")[0] + ".cli"  # host.cli, or mpy_fil.host.cli installed (setup.py)
    return os.path.basename(sys.argv[0] or "") == "mpy-fil" or getattr(spec, "name", None) == cli


if _the_program():
    sys.excepthook = _stopped_uncaught
    sys.unraisablehook = _stopped_unraisable
    install()
