"""``--hil-coverage``: every rig runs its firmware on the ``settrace`` interpreter and writes
its coverage (docs/coverage.md).

Before any test runs (in the controller under pytest-xdist) the variant is built if it is
not there (each ``--mpy-version`` version's: coverage per version, docs/versions.md) and the
coverage folder's earlier data removed. Each rig writes
``.coverage.<test>.rig<n>`` there (the test's node id as its coverage context, so the HTML
shows which tests ran each line); at the end of the
session they are merged into ``.coverage``, the HTML written to ``html/`` and linked from
the HIL report (``--hil-report``), and the total printed. The folder: ``--hil-coverage-dir``,
else ``coverage/`` beside the HIL report, else the rigs' artefacts root's.
"""

import re
from pathlib import Path

import pytest

from host.core import interpreter
from host.core.errors import HarnessError
from host.core.paths import REPO
from host.coverage import collector, session
from host.pytest_plugin import mpy_versions
from host.pytest_plugin.session_report import is_worker

PLUGIN_NAME = "hil-coverage"


def addoption(group) -> None:
    group.addoption(
        "--hil-coverage",
        action="store_true",
        help="run the firmware on the line-tracing interpreter and write its line and branch coverage "
        "(coverage.py data, per scenario and merged, and HTML; docs/coverage.md)",
    )
    group.addoption("--hil-coverage-dir", metavar="DIR", type=Path, help="with --hil-coverage: where it goes")


def folder(config) -> Path:
    chosen = config.getoption("--hil-coverage-dir", None)
    if chosen:
        return Path(chosen).resolve()
    report = config.getoption("--hil-report", None)
    if report:
        return Path(report).resolve().parent / "coverage"
    out = config.getoption("--hil-out", None)
    return (Path(out) if out else REPO / "build" / "hil").resolve() / "coverage"


def configure(config) -> None:
    """Register the plugin object when coverage is asked for; build the variant once."""
    if not config.getoption("--hil-coverage", False):
        return
    if not is_worker(config):
        try:
            for version in mpy_versions.versions(config) or [None]:  # (--mpy-version: each one's)
                interpreter.build_variant("settrace", version=version)
        except HarnessError as e:
            raise pytest.UsageError(f"--hil-coverage: {e}") from None
        session.clear(folder(config))
    config.pluginmanager.register(HilCoverage(config), PLUGIN_NAME)


def data_file(config, nodeid: str, n: int) -> Path | None:
    """Where a test's rig ``n`` writes its coverage, or None without ``--hil-coverage``."""
    plugin = config.pluginmanager.get_plugin(PLUGIN_NAME)
    if plugin is None:
        return None
    name = re.sub(r"[^A-Za-z0-9_.-]+", "_", nodeid).strip("_")
    path = plugin.folder / f"{session.MERGED}.{name}.rig{n}"
    collector.name_context(path, nodeid)  # (the test is the context of each line its rigs run)
    return path


class HilCoverage:
    def __init__(self, config):
        self.config = config
        self.folder = folder(config)
        self.total: float | None = None
        self.error = ""

    @pytest.hookimpl(tryfirst=True)
    def pytest_sessionfinish(self):
        """Merge and write the HTML before the HIL report is written (it links them)."""
        if is_worker(self.config):
            return
        try:
            merged = session.merge(self.folder)
            if merged is not None:
                self.total = session.report(merged, self.folder / "html")
        except HarnessError as e:
            self.error = str(e)
        reporter = self.config.pluginmanager.get_plugin("hil-session-report")
        collector = getattr(reporter, "collector", None)
        if collector is not None:
            collector.coverage = self.summary()

    def summary(self) -> dict | None:
        if self.total is None:
            return {"error": self.error} if self.error else None
        return {"total": self.total, "html": self.folder / "html" / "index.html", "data": self.folder / session.MERGED}

    def pytest_terminal_summary(self, terminalreporter):
        if is_worker(self.config):
            return
        if self.total is not None:
            line = f"firmware coverage: {self.total:.0f}% of lines and branches: {self.folder / 'html' / 'index.html'}"
            terminalreporter.write_line(line + f" (data: {self.folder / session.MERGED})")
        else:
            terminalreporter.write_line(f"firmware coverage: none written ({self.error or 'no rig ran'})")
