"""The session's HIL summary, made where the test reports arrive: the scenario result lines
and budget table (``--hil-table``; ``--hil-table-full``, alone or not: every budget of every
rig) and the HTML report (``--hil-report``).

Each test's teardown report carries its rigs (``report.hil_rigs``: label, trace folder,
budget rows, MicroPython version, plots already made), an attribute that pytest-xdist
ships from a worker with the rest of the report. So one process sees every rig: the
session's own without xdist, the controller with it (``make hil`` runs ``-n auto``); a
worker only runs tests and writes trace folders (and their plots).
"""

from pathlib import Path

import pytest

from host.report.session import ReportCollector
from host.report.table import WIDTH, format_summary, format_table
from host.rig.config import verdicts

RIGS_ATTRIBUTE = "hil_rigs"


def is_worker(config) -> bool:
    """A pytest-xdist worker: it runs tests, the controller reports them."""
    return hasattr(config, "workerinput")


class SessionReport:
    """A plugin object (registered by the plugin's ``pytest_configure``) that folds every
    test report into the table and the HTML report."""

    def __init__(self, config):
        self.config = config
        path = config.getoption("--hil-report", None)
        self.collector = ReportCollector(path) if path else None
        self.rows: list[dict] = []

    def pytest_runtest_logreport(self, report):
        collector = self.collector
        name = report.nodeid.split("::")[-1]
        for rig in getattr(report, RIGS_ATTRIBUTE, None) or ():
            self.rows.extend({"scenario": name, "rig": rig["label"], **row} for row in rig["rows"])
            if collector is not None:
                collector.add_rig(report.nodeid, name, rig)
        if collector is None:
            return
        collector.count(report.nodeid, report)
        if "hil" in report.keywords:
            collector.add_phase(report.nodeid, name, report)

    def pytest_terminal_summary(self, terminalreporter):
        full = self.config.getoption("--hil-table-full")  # (alone, it asks for the table too)
        if not self.config.getoption("--hil-table") and not full:
            return
        results = [
            (report.nodeid.split("::", 1)[-1], report.outcome, value)
            for reports in terminalreporter.stats.values()
            for report in reports
            if getattr(report, "when", None) == "call"
            for key, value in getattr(report, "user_properties", ())
            if key == "result"
        ]
        if results:  # what each scenario measured: record_property("result", "...") in a test
            terminalreporter.section("scenario results")
            for name, outcome, text in results:
                terminalreporter.write_line(f"{outcome:<7} {name}: {text}")
        if self.rows:
            terminalreporter.section("timing budgets (us of virtual time unless marked wall)")
            if full:
                terminalreporter.write_line(verdicts.headline(self.rows)[1])
                terminalreporter.write_line(format_table(self.rows))
            else:
                failed = {r.nodeid.split("::")[-1] for r in terminalreporter.stats.get("failed", ())}
                width = getattr(getattr(terminalreporter, "_tw", None), "fullwidth", WIDTH)
                terminalreporter.write_line(format_summary(self.rows, failed, width=max(width, 60)))

    @pytest.hookimpl(trylast=True)
    def pytest_sessionfinish(self):
        if self.collector is not None:
            self.collector.write()

    def pytest_unconfigure(self):
        """The report's path, as the session's last line."""
        tr = self.config.pluginmanager.get_plugin("terminalreporter")
        if self.collector is not None and tr is not None and self.collector.path.is_file():
            tr.write_line(f"HIL report: {self.collector.path.resolve()}", bold=True)


def rig_record(label: str, rig, rows: list[dict], plots: tuple[list[Path], str] = ([], "")) -> dict:
    """What a report needs of one stopped rig, in types a worker can send; ``plots``:
    (the plots made of its trace folder, why none could be)."""
    return {
        "label": label,
        "folder": str(rig.artefacts) if rig.artefacts else "",
        "rows": rows,
        "micropython": rig.micropython_version or "",
        "plots": [str(p) for p in plots[0]],
        "plot_error": plots[1],
    }
