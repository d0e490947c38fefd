"""Collects a HIL session's scenarios (outcome, rigs, budgets) for the HTML report, then
plots every recorded rig and writes the report (:mod:`host.report`).

The pytest plugin feeds it; it knows nothing of pytest beyond the report objects'
``when``/``outcome``/``duration``/``longreprtext`` fields.
"""

import json
import multiprocessing
import os
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from host.artefacts.folder import HEADER
from host.report.html import RigResult, Scenario, write_report

MESSAGE_MAX_CHARS = 6000


class ReportCollector:
    def __init__(self, path: Path):
        self.path = Path(path)
        self.scenarios: dict[str, Scenario] = {}
        self.micropython = ""
        self.totals: dict[str, int] = {}  # every test of the session, as pytest counts them
        self._counted: set[str] = set()
        self.skipped: list[tuple[str, str]] = []  # (test, why) of every skipped test
        self.coverage: dict | None = None  # the firmware's coverage (host/pytest_plugin/hil_coverage.py)

    def count(self, nodeid: str, report) -> None:
        """Any test's phase: its outcome into the session's totals (once per test)."""
        failed = report.outcome == "failed"
        if report.when == "call" or failed or report.outcome == "skipped":
            outcome = ("failed" if report.when == "call" else "error") if failed else report.outcome
            if nodeid not in self._counted:
                self._counted.add(nodeid)
                self.totals[outcome] = self.totals.get(outcome, 0) + 1
                if outcome == "skipped":
                    self.skipped.append((nodeid, skip_reason(report)))

    def scenario(self, nodeid: str, name: str) -> Scenario:
        if nodeid not in self.scenarios:
            self.scenarios[nodeid] = Scenario(name=name, nodeid=nodeid, outcome="passed")
        return self.scenarios[nodeid]

    def add_rig(self, nodeid: str, name: str, rig: dict) -> None:
        """One stopped rig of a test: ``label``, ``folder`` (its trace folder, '' for none),
        ``rows`` (its budget rows), ``micropython`` and ``plots`` (those already made)."""
        folder = Path(rig["folder"]) if rig.get("folder") else None
        result = RigResult(folder.name if folder else rig.get("label", "rig"), folder, list(rig.get("rows", ())))
        result.plots = [Path(p) for p in rig.get("plots", ())]
        if rig.get("plot_error"):
            result.budgets.append(_plot_failure(rig["plot_error"]))
        self.scenario(nodeid, name).rigs.append(result)
        version = rig.get("micropython", "").split(";")[0]
        if version and version not in self.micropython.split(", "):  # (pytest --mpy-version: each one)
            self.micropython = f"{self.micropython}, {version}" if self.micropython else version

    def add_phase(self, nodeid: str, name: str, report) -> None:
        """One of setup/call/teardown finished: fold its outcome into the scenario's."""
        s = self.scenario(nodeid, name)
        s.duration_s += report.duration
        s.result = s.result or next((v for k, v in getattr(report, "user_properties", ()) if k == "result"), "")
        if report.outcome == "failed":
            s.outcome = "failed" if report.when == "call" else "error"
            text = report.longreprtext
            if len(text) > MESSAGE_MAX_CHARS:
                text = "...\n" + text[-MESSAGE_MAX_CHARS:]
            s.message = (s.message + "\n\n" + text).strip()
        elif report.outcome == "skipped" and s.outcome == "passed":
            s.outcome = "skipped"
            s.message = report.longreprtext[-MESSAGE_MAX_CHARS:]

    def write(self, workers: int | None = None) -> Path:
        """Plot every recorded rig (in parallel) and write the report; returns its path.
        Scenarios are the tests that ran rigs, and every test that failed."""
        rigs = [r for s in self.scenarios.values() for r in s.rigs if r.folder and (r.folder / HEADER).is_file()]
        unplotted = [r for r in rigs if not r.plots]  # a pytest-xdist worker plots its own rigs
        results = _plot_all([r.folder for r in unplotted], workers)
        for rig, (plots, error) in zip(unplotted, results):
            rig.plots = plots
            if error:
                rig.budgets = rig.budgets + [_plot_failure(error)]
        for rig in rigs:
            rig.header = json.loads((rig.folder / HEADER).read_text(encoding="utf-8"))
        shown = [s for s in self.scenarios.values() if s.rigs or s.outcome in ("failed", "error")]
        return write_report(
            self.path,
            shown,
            micropython=self.micropython,
            totals=self.totals or None,
            skipped=sorted(self.skipped),
            coverage=self.coverage,
        )


def skip_reason(report) -> str:
    """A skipped test's reason, as pytest's ``-rs`` prints it (without "Skipped: ")."""
    longrepr = report.longrepr
    text = longrepr[2] if isinstance(longrepr, tuple) and len(longrepr) == 3 else str(longrepr or "")
    return str(text).removeprefix("Skipped: ") or "no reason given"


def _plot_failure(error: str) -> dict:
    return {"budget": "(plots)", "limit": f"plotting failed: {error}"}


def plot_one(folder: Path) -> tuple[list[Path], str]:
    """Every plot of one trace folder, or none and why."""
    from host.report.plots import plot_trace

    try:
        return plot_trace(folder), ""
    except Exception as e:  # one unplottable trace must not cost the whole report
        return [], f"{type(e).__name__}: {e}"


def _plot_all(folders: list[Path], workers: int | None) -> list[tuple[list[Path], str]]:
    from host.report import plots  # noqa: F401  (once here, not in every worker)

    workers = workers or min(len(folders), os.cpu_count() or 1)
    if workers <= 1 or len(folders) <= 1:
        return [plot_one(f) for f in folders]
    methods = multiprocessing.get_all_start_methods()
    context = multiprocessing.get_context("fork" if "fork" in methods else "spawn")
    with ProcessPoolExecutor(max_workers=workers, mp_context=context) as pool:
        return list(pool.map(plot_one, folders))
