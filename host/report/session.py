"""Collects a HIL session's scenarios (outcome, rigs, budgets) for the HTML report, then
plots every recorded rig and writes the report (:mod:`host.report`).

The pytest plugin feeds it; it knows nothing of pytest beyond the report objects'
``when``/``outcome``/``duration``/``longreprtext`` fields.
"""

import multiprocessing
import os
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from host.artefacts.folder import HEADER, load_trace
from host.report.html import RigResult, Scenario, write_report

MESSAGE_MAX_CHARS = 6000


class ReportCollector:
    def __init__(self, path: Path):
        self.path = Path(path)
        self.scenarios: dict[str, Scenario] = {}
        self.micropython = ""
        self.totals: dict[str, int] = {}  # every test of the session, as pytest counts them
        self._counted: set[str] = set()

    def count(self, nodeid: str, report) -> None:
        """Any test's phase: its outcome into the session's totals (once per test)."""
        failed = report.outcome == "failed"
        if report.when == "call" or failed or report.outcome == "skipped":
            outcome = ("failed" if report.when == "call" else "error") if failed else report.outcome
            if nodeid not in self._counted:
                self._counted.add(nodeid)
                self.totals[outcome] = self.totals.get(outcome, 0) + 1

    def scenario(self, nodeid: str, name: str) -> Scenario:
        if nodeid not in self.scenarios:
            self.scenarios[nodeid] = Scenario(name=name, nodeid=nodeid, outcome="passed")
        return self.scenarios[nodeid]

    def add_rig(self, nodeid: str, name: str, rig, budget_rows: list[dict]) -> None:
        folder = rig.artefacts
        self.scenario(nodeid, name).rigs.append(RigResult(folder.name if folder else "rig", folder, budget_rows))
        if rig.micropython_version and not self.micropython:
            self.micropython = rig.micropython_version.split(";")[0]

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
        results = _plot_all([r.folder for r in rigs], workers)
        for rig, (plots, error) in zip(rigs, results):
            rig.plots = plots
            rig.header = load_trace(rig.folder).header
            if error:
                rig.budgets = rig.budgets + [{"budget": "(plots)", "limit": f"plotting failed: {error}"}]
        shown = [s for s in self.scenarios.values() if s.rigs or s.outcome in ("failed", "error")]
        return write_report(self.path, shown, micropython=self.micropython, totals=self.totals or None)


def _plot_one(folder: Path) -> tuple[list[Path], str]:
    from host.report.plots import plot_trace

    try:
        return plot_trace(folder), ""
    except Exception as e:  # one unplottable trace must not cost the whole report
        return [], f"{type(e).__name__}: {e}"


def _plot_all(folders: list[Path], workers: int | None) -> list[tuple[list[Path], str]]:
    import host.report.plots  # noqa: F401  (once here, not in every worker)

    workers = workers or min(len(folders), os.cpu_count() or 1)
    if workers <= 1 or len(folders) <= 1:
        return [_plot_one(f) for f in folders]
    methods = multiprocessing.get_all_start_methods()
    context = multiprocessing.get_context("fork" if "fork" in methods else "spawn")
    with ProcessPoolExecutor(max_workers=workers, mp_context=context) as pool:
        return list(pool.map(_plot_one, folders))
