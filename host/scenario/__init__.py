"""Wokwi automation scenarios (``*.test.yaml``) run against a rig in virtual time:
``mpy-fil scenario``, and a pytest item per scenario file (docs/wokwi-scenarios.md)."""

from host.scenario.runner import ScenarioRun, StepFailed
from host.scenario.scenario import Scenario, ScenarioError, load_scenario
from host.scenario.session import find_rig, load_rig_for, run_scenario

__all__ = [
    "Scenario",
    "ScenarioError",
    "ScenarioRun",
    "StepFailed",
    "find_rig",
    "load_rig_for",
    "load_scenario",
    "run_scenario",
]
