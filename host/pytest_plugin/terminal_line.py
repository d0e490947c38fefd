"""A long mission's progress in a pytest session: on a terminal, one line under the test
dots, rewritten in place and cleared before the test's result is written; in a log, a
line now and then (:class:`host.report.progress.MissionProgress` decides when). A
pytest-xdist worker writes its lines, named by the worker, to its stderr, which the
controller's terminal or log shows (a worker's stdout is its link to the controller)."""

import contextlib
import os
import sys

from host.report.progress import MissionProgress

_screens: list = []  # the session's one progress line (pytest_runtest_logreport has no config)


def mission_progress(config, label: str, mission_s: float | None = None) -> MissionProgress | None:
    """A rig's ``progress`` callback for this session (None without a terminal reporter);
    ``mission_s``: the scenario's mission length, carried across its runs."""
    if hasattr(config, "workerinput"):  # a pytest-xdist worker: its stdout goes nowhere, its stderr to the log
        worker = config.workerinput.get("workerid", "?")
        return MissionProgress(label, line=lambda text: _to_stderr(config, f"[{worker}] {text}"), mission_s=mission_s)
    tr = config.pluginmanager.get_plugin("terminalreporter")
    if tr is None:
        return None
    if getattr(tr, "isatty", False):
        if not _screens:
            _screens.append(_ScreenLine(config))
        return MissionProgress(label, rewrite=_screens[0].show, mission_s=mission_s)
    return MissionProgress(
        label, line=lambda text: _with_terminal(config, lambda t: t.write_line(text)), mission_s=mission_s
    )


def clear_progress_lines() -> None:
    for screen in _screens:
        screen.clear()


class _ScreenLine:
    """One line on the terminal under pytest's progress dots, the cursor put back after
    the dots when cleared. Written to the terminal's file descriptor, past pytest's
    writer, so that its own idea of the current line stays right."""

    def __init__(self, config):
        self.config = config
        self.column = None  # where the dots ended, while the line is shown

    def show(self, text: str) -> None:
        def write(tr) -> None:
            if self.column is None:
                tw = getattr(tr, "_tw", None)
                self.column = getattr(tw, "width_of_current_line", 0)
                _raw(tr, "\n")
            _raw(tr, f"\r\x1b[K{text}")

        _with_terminal(self.config, write)

    def clear(self) -> None:
        if self.column is None:
            return
        column, self.column = self.column, None
        back = f"\x1b[1A\x1b[{column}C" if column else "\x1b[1A"
        _with_terminal(self.config, lambda tr: _raw(tr, f"\r\x1b[K{back}"))


def _raw(tr, text: str) -> None:
    tr.flush()
    os.write(sys.stdout.fileno(), text.encode())


def _to_stderr(config, text: str) -> None:
    """A line on the process's own stderr, around pytest's output capture."""
    capman = config.pluginmanager.get_plugin("capturemanager")
    with capman.global_and_fixture_disabled() if capman is not None else contextlib.nullcontext():
        os.write(2, (text + "\n").encode())


def _with_terminal(config, write) -> None:
    """Write to the terminal from inside a test: around pytest's output capture."""
    tr = config.pluginmanager.get_plugin("terminalreporter")
    capman = config.pluginmanager.get_plugin("capturemanager")
    if tr is None:
        return
    if capman is None:
        write(tr)
        return
    with capman.global_and_fixture_disabled():
        write(tr)
