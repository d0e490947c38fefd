"""A scenario file run whole: the rig it runs against (a ``rig.toml`` in its folder or
the nearest folder above), checked against the scenario before anything starts, started
with a trace folder, the steps run, the outcome (steps, simulated and wall time)."""

import time
from dataclasses import dataclass, field
from pathlib import Path

from host.core import safefs
from host.core.paths import output_root
from host.rig.hardware.wiring import PROBE_PREFIX
from host.scenario.runner import ScenarioRun, known_ids, part_pins
from host.scenario.scenario import ScenarioError, load_scenario
from sim_plant.controls import ControlError
from sim_plant.names import unknown

RIG_NAME = "rig.toml"
DIAGRAM_NAME = "diagram.json"


def find_rig(scenario_path) -> Path:
    """The rig a scenario runs against: ``rig.toml`` (or else a Wokwi project's
    ``diagram.json``) in its folder or the nearest folder above it."""
    start = Path(scenario_path).resolve().parent
    for folder in (start, *start.parents):
        for name in (RIG_NAME, DIAGRAM_NAME):
            candidate = folder / name
            if candidate.is_file():
                return candidate
    raise ScenarioError(f"{scenario_path}: no {RIG_NAME} or {DIAGRAM_NAME} in its folder or a folder above ({start})")


def load_rig_for(scenario_path):
    """The rig (an App, as ``load_rig`` returns it) a scenario runs against: a rig file,
    or a Wokwi project read as one (:func:`host.rig.config.wokwi.project.rig_from_project`)."""
    from host.rig.config.rigfile import load_rig

    found = find_rig(scenario_path)
    if found.name == DIAGRAM_NAME:
        from host.rig.config.wokwi.project import rig_from_project

        return rig_from_project(found.parent)
    return load_rig(found)


@dataclass
class Outcome:
    scenario: object
    artefacts: Path
    results: list = field(default_factory=list)
    t_end_us: int = 0
    wall_s: float = 0.0


def check_steps(scenario, rig) -> None:
    """Every part-id, control and value the steps name exists on this rig, before it
    starts: a ScenarioError names the line and what the rig has."""
    ids = known_ids(rig.app, rig.plant)
    probes = {v[len(PROBE_PREFIX) :] for v in rig.app.wiring.values() if v.startswith(PROBE_PREFIX)}
    probes -= {name.split(".", 1)[0] for name in {**rig.plant.inputs, **rig.plant.outputs}}
    parts = {p.name: p for p in rig.plant.catalogue_parts}
    for step in scenario.steps:
        where = f"{scenario.path}:{step.line}: {step.kind}"
        part = step.args.get("part")
        if step.kind == "set-control":
            if part not in parts:
                with_controls = ", ".join(n for n, p in parts.items() if p.CONTROLS) or "none"
                close = unknown(part, [n for n, p in parts.items() if p.CONTROLS]).rpartition(")")[2]
                raise ScenarioError(
                    f"{where}: no part {part!r} on the rig (parts with controls: {with_controls}){close}"
                )
            try:
                parts[part].control_change(step.args["control"], step.args["value"])
            except ControlError as e:
                raise ScenarioError(f"{where}: {e}") from None
        elif part is not None and part not in ids and not _board_pin(rig, step.args["pin"]):
            raise ScenarioError(
                f"{where}: no part or probe {part!r} on the rig {unknown(part, sorted(ids), what='has')}, "
                f"and {step.args['pin']!r} is no board pin"
            )
        elif part in ids and part not in probes:
            pins = part_pins(rig.plant, part)
            if step.args["pin"].lower() not in {p.lower() for p in pins}:
                known = unknown(step.args["pin"], pins, what="its pins")
                raise ScenarioError(f"{where}: pin: part {part!r} has no pin {step.args['pin']!r} {known}")


def _board_pin(rig, pin: str) -> bool:
    """``pin`` names one of the board's pins: its rig name, or its number (GP25, D2, 25)."""
    _folder, pins = rig.app.board_files(rig.board)
    return pin in (pins or {}) or pin.upper().lstrip("GPD").isdigit()


def prepare(path, timeout_us: int | None = None) -> tuple:
    """(the scenario in ``path``, with ``timeout_us`` over its own; the rig's App)."""
    scenario = load_scenario(path)
    if timeout_us is not None:
        scenario = type(scenario)(scenario.path, scenario.name, scenario.steps, timeout_us, scenario.author)
    return scenario, load_rig_for(path)


def run_on(rig, scenario, echo=None) -> Outcome:
    """Run ``scenario``'s steps on ``rig`` (started); StepFailed when a step fails."""
    outcome = Outcome(scenario, rig.artefacts)
    wall0 = time.perf_counter()
    run = ScenarioRun(rig, scenario, echo)
    try:
        outcome.results = run.run()
    finally:
        outcome.results = run.results
        outcome.t_end_us = rig.t_us
        outcome.wall_s = time.perf_counter() - wall0
    return outcome


def run_scenario(path, *, out: Path | None = None, seed: int = 0, timeout_us: int | None = None, echo=None) -> Outcome:
    """Run the scenario in ``path`` against its rig, with a trace folder (``out``, or
    ``build/scenarios/<name>`` beside the rig); StepFailed when a step fails."""
    from host.rig import Recording, Rig, RigSpec

    scenario, app = prepare(path, timeout_us)
    stem = Path(path).name.split(".")[0]
    root = output_root(app.rig_file)
    out = safefs.output_folder(  # (never the firmware folder, around it or inside it but for build/)
        Path(out) if out is not None else root / "scenarios" / f"{app.name}-{stem}",
        what="--out",
        inputs={"the firmware folder": app.path},
        owned={"the firmware folder": root},
        base=None if out is not None else root.parent,
        create=False,  # (made as the run starts: a scenario refused before it leaves none)
    )
    rig = Rig(RigSpec(app, seed=seed, allow_exit=True), Recording(trace=True, record=True, artefacts=out))
    check_steps(scenario, rig)
    wall0 = time.perf_counter()
    with rig:
        outcome = run_on(rig, scenario, echo)
    outcome.wall_s = time.perf_counter() - wall0  # (with the firmware's start and the trace folder written)
    return outcome
