"""A failed test's report leads with the harness's message, not with the harness's source.

pytest prints a failure's traceback frame by frame, each with its source, and the message
last: a test that fails in ``rig.expect`` showed 20-40 lines of the harness (``Rig.expect``,
``waits.expect`` and its ``raise``) before the line that says what was expected. When the
harness raised on purpose, its frames say nothing a user can act on, so the report becomes

    E   ExpectTimeout: expected the console to match 'ready' within 1 simulated s ...
    E   seed: 1
    E   artefacts: build/hil/test_mybot/test_mybot_says_ready/rig0
    _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _
    test_mybot.py:6: in test_mybot_says_ready
        rig.expect("ready", timeout_s=1)

the message, then each frame of the user's own code (the test, its helpers, its
conftest.py) that led there, one line each. "On purpose": the error is one of the
harness's own (:class:`host.core.errors.HarnessError`), or any other exception raised by
an explicit ``raise`` in the harness's code (``budget.check()``'s AssertionError, a
``make_rig`` keyword's TypeError), or an ``assert`` of its own (a rig file run as a test).
Anything else that fails inside the harness (a ``KeyError`` in its code) is a harness bug
and keeps pytest's full traceback, as do ``--fulltrace`` and ``--tb=native``, ``line`` or
``no``, and an item that words its own failures (a Wokwi scenario's). The harness's own
tests (``host/tests``, ``sim_plant/tests``) count as a user's code.
"""

from pathlib import Path

import pytest
from _pytest._code.code import ExceptionChainRepr, FormattedExcinfo, ReprEntry, ReprFileLocation, ReprTraceback

from host.core.errors import HarnessError
from host.core.paths import HOST, REPO

HARNESS = (HOST, REPO / "sim_plant")
"""The harness's code (in a checkout and as installed: ``sim_plant`` is beside ``host``)."""
STYLES = ("auto", "long", "short")
"""The traceback styles this formats (the others are pytest's as they are)."""
FAIL = "E   "


def harness_frame(path) -> bool:
    """``path`` is the harness's code (not its tests)."""
    try:
        path = Path(path).resolve()
    except (TypeError, OSError):
        return False
    return any(path.is_relative_to(top) for top in HARNESS) and "tests" not in path.parts[len(REPO.parts) :]


def on_purpose(excinfo) -> bool:
    """The harness raised this error as its message (not a bug inside it)."""
    if excinfo.errisinstance(HarnessError):
        return True
    if not excinfo.errisinstance(Exception) or not excinfo.traceback:
        return False
    last = excinfo.traceback[-1]
    if not harness_frame(last.path):
        return False
    return _statement(last).startswith("raise ") or _harness_assert(excinfo)


def _statement(entry) -> str:
    try:
        return str(entry.statement).lstrip()
    except (IndexError, OSError, ValueError):
        return ""


def _harness_assert(excinfo) -> bool:
    """An ``assert`` statement of the harness's failed (pytest rewrote it: its message
    ends with pytest's explanation)."""
    if not excinfo.errisinstance(AssertionError) or not excinfo.traceback:
        return False
    last = excinfo.traceback[-1]
    return harness_frame(last.path) and _statement(last).startswith("assert ")


def lead_with_message(item, call, report) -> None:
    """Rewrite a failed setup or call's report of a harness error (see the module's text)."""
    excinfo = call.excinfo
    config = item.config
    if not report.failed or excinfo is None or report.when not in ("setup", "call"):
        return
    if type(item).repr_failure is not pytest.Function.repr_failure:  # (an item that words its own: a scenario's)
        return
    if config.getoption("fulltrace", False) or config.getoption("tbstyle", "auto") not in STYLES:
        return
    if not on_purpose(excinfo):
        return
    frames = [e for e in _shown(item, excinfo) if not harness_frame(e.path)]
    formatter = FormattedExcinfo(style="short", abspath=False, tbfilter=False)
    entries = [formatter.repr_traceback_entry(e) for e in frames]  # (no excinfo: no E lines of their own)
    message = message_of(excinfo.value)
    if _harness_assert(excinfo):
        message = message.split("\nassert ", 1)[0]  # (the assert's own words, not pytest's rewrite of it)
    head = ReprEntry([FAIL + line for line in message.splitlines() or [""]], None, None, None, "long")
    last = frames[-1] if frames else (excinfo.traceback[-1] if excinfo.traceback else None)
    crash = ReprFileLocation(formatter._makepath(last.path), last.lineno + 1, message) if last is not None else None
    longrepr = ExceptionChainRepr([(ReprTraceback([head, *entries], None, "short"), crash, None)])
    for name, content, sep in getattr(report.longrepr, "sections", ()):
        longrepr.addsection(name, content, sep)
    report.longrepr = longrepr


def message_of(error: BaseException) -> str:
    """``Type: message``, with what caused it and its notes (no traceback of either)."""
    text = f"{type(error).__name__}: {error}".rstrip()
    cause = error.__cause__ or (None if error.__suppress_context__ else error.__context__)
    if cause is not None:
        text += f"\n(from {type(cause).__name__}: {cause})"
    for note in getattr(error, "__notes__", ()):
        text += f"\n{note}"
    return text


def _shown(item, excinfo):
    """The traceback as pytest would show it (cut to the test's own frames), hidden
    frames (``__tracebackhide__``) out."""
    try:
        return list(item._traceback_filter(excinfo))
    except (AttributeError, TypeError, ValueError):  # (an item that is no Function: a rig file's)
        return [e for e in excinfo.traceback if not e.ishidden(excinfo)]
