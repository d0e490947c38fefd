"""A pytest item per Wokwi scenario file (``*.test.yaml``), collected by the plugin
(``host/pytest_plugin``): the scenario's steps run on a rig from ``make_rig`` (so the
rig's seed, artefacts and budgets go to JUnit and the report as every test's do), its
trace folder always kept; a failing step fails the item with its line and what was seen."""

import pytest

from host.scenario.runner import StepFailed
from host.scenario.scenario import ScenarioError
from host.scenario.session import check_steps, prepare, run_on

SUFFIX = ".test.yaml"


class ScenarioItem(pytest.Function):
    """The scenario's test: a failing step (or a file that cannot run) is its message
    alone, no traceback of the harness."""

    def repr_failure(self, excinfo, style=None):
        if isinstance(excinfo.value, (StepFailed, ScenarioError)):
            return str(excinfo.value)
        return super().repr_failure(excinfo, style)


class ScenarioFile(pytest.File):
    """A scenario file: one test, its steps."""

    def collect(self):
        yield ScenarioItem.from_parent(self, name="scenario", callobj=_run_scenario_file)


def collect_scenario(file_path, parent):
    if file_path.name.endswith(SUFFIX):
        return ScenarioFile.from_parent(parent, path=file_path)
    return None


def _run_scenario_file(make_rig, request):
    """The scenario's steps against its rig (rig.toml in its folder or above), in virtual time."""
    scenario, app = prepare(request.node.path)
    rig = make_rig(app, seed=0, allow_exit=True, record=True, trace=True)
    check_steps(scenario, rig)
    outcome = run_on(rig, scenario)
    request.node.user_properties += [
        ("scenario.steps", len(outcome.results)),
        ("scenario.simulated_s", outcome.t_end_us / 1e6),
        ("scenario.wall_s", round(outcome.wall_s, 3)),
    ]
