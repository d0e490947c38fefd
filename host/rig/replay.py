"""Replay a trace: drive the firmware with the recorded sensor stream and compare what it
drives with what it drove.

The plant is a :class:`ReplayPlant`, a :class:`sim_plant.scripted.ScriptedPlant` whose
script is every recorded plant-output change, in recorded order. The firmware runs in
lockstep for the recorded length; its outputs (actuators, probes, bare pins) are
compared one by one with the recorded ones and the first difference is reported. The
same firmware on the same recording gives none: a difference means the firmware, the
shim or the rig changed behaviour (or the trace was taken in real time, which no
replay reproduces).

A replay never runs past what was recorded: the header's ``t_end_us`` must lie within the
recording (no earlier than its last change, no later than a truth period past its last
truth row). A partial recording (a run stopped by a signal, docs/traces.md) is replayed to
its cut, and only what happened before the cut's instant is compared: the cut may fall
between two outputs of one instant.
"""

from dataclasses import dataclass
from pathlib import Path

from host.artefacts.checks import partial_reason
from host.artefacts.folder import TraceData, load_trace
from host.artefacts.recorder import ROLE_ACTUATOR, ROLE_SENSOR
from host.core.errors import ConfigError
from host.rig.apps import get_app
from host.rig.rig import Rig
from sim_plant.scripted import ScriptedPlant


class ReplayPlant(ScriptedPlant):
    """A ScriptedPlant that keeps the recorded order of same-time changes and can be
    snapshotted cheaply (the rig rolls speculative batches back)."""

    def __init__(self, script, *, outputs, inputs, initial):
        super().__init__((), outputs=outputs, inputs=inputs, initial=initial)
        unknown = sorted({name for _t, name, _v in script} - set(outputs))
        if unknown:
            raise ConfigError(f"replay: the recording drives unknown plant outputs {unknown}")
        self.script = sorted(script, key=lambda e: e[0])  # stable: same-time order as recorded

    def snapshot(self):
        return self._t_us, self._next, dict(self.values), len(self.log)

    def restore(self, snap) -> None:
        self._t_us, self._next, values, n_log = snap
        self.values = dict(values)
        del self.log[n_log:]


@dataclass
class Difference:
    index: int  # position in the firmware's output stream
    t_us: int
    recorded: tuple | None  # (t_us, signal, value), None past the recording's end
    replayed: tuple | None

    def __str__(self) -> str:
        def show(e):
            return "nothing" if e is None else f"{e[1]} = {e[2]} at t={e[0] / 1e6:.6f} s"

        return (
            f"first difference at output #{self.index} (t={self.t_us / 1e6:.6f} s): "
            f"recorded {show(self.recorded)}, replay {show(self.replayed)}"
        )


@dataclass
class ReplayResult:
    recorded: int  # firmware outputs in the recording
    replayed: int  # firmware outputs in the replay
    difference: Difference | None
    folder: Path  # the replay's own trace folder
    partial: str | None = None  # why the recording is partial: compared up to its cut

    @property
    def same(self) -> bool:
        return self.difference is None


def replay_plant(trace: TraceData) -> ReplayPlant:
    h = trace.header
    signals = h.get("signals", {})
    outputs = {n: i["kind"] for n, i in signals.items() if i["role"] == ROLE_SENSOR}
    inputs = {n: i["kind"] for n, i in signals.items() if i["role"] == ROLE_ACTUATOR}
    try:
        script = [(t, n, bytes.fromhex(v) if outputs[n] == "bytes" else v) for t, n, v in trace.events if n in outputs]
        initial = {n: (bytes.fromhex(v) if outputs.get(n) == "bytes" else v) for n, v in h.get("initial", {}).items()}
    except (ValueError, TypeError) as e:
        raise ConfigError(f"trace {trace.folder}: a recorded byte value is not hex text ({e})") from None
    return ReplayPlant(script, outputs=outputs, inputs=inputs, initial=initial)


def recorded_end_us(trace: TraceData) -> int:
    """The header's ``t_end_us``, checked against what was recorded."""
    h = trace.header
    t_end_us = h["t_end_us"]
    last_event_us = max((e[0] for e in trace.events), default=0)
    t_truth = trace.truth.get("t_us")
    last_truth_us = int(t_truth[-1]) if t_truth is not None and len(t_truth) else 0
    limit_us = last_truth_us + h.get("truth_period_us", 50_000)
    if not last_event_us <= t_end_us <= limit_us:
        raise ConfigError(
            f"trace {trace.folder}: header.json t_end_us {t_end_us} is outside what was recorded "
            f"(changes up to {last_event_us}, truth up to {last_truth_us}); the header does not belong to these files"
        )
    return t_end_us


def replay(folder, artefacts, *, watchdog_s: float = 5.0, progress=None) -> ReplayResult:
    """Run the recorded app and board against the recorded sensor stream; compare."""
    trace = load_trace(folder)
    h = trace.header
    if h.get("mode") != "lockstep":
        raise ConfigError(f"trace {folder}: recorded in {h.get('mode')} mode; only lockstep runs replay exactly")
    t_end_us = recorded_end_us(trace)
    partial = partial_reason(h)
    try:
        rig = _replay_rig(trace, Path(artefacts), watchdog_s=watchdog_s, progress=progress)
    except ConfigError as e:  # (an app, board or option the header names that is not there)
        raise ConfigError(f"trace {folder}: header.json: {e}") from None
    with rig:
        rig.run_until(t_end_us)
    before = (lambda t: t < t_end_us) if partial else (lambda t: t <= t_end_us)
    recorded = [e for e in trace.firmware_outputs() if before(e[0])]
    replayed = [e for e in rig.recorder.firmware_outputs() if before(e[0])]
    difference = first_difference(recorded, replayed)
    return ReplayResult(len(recorded), len(replayed), difference, Path(artefacts), partial)


def _replay_rig(trace: TraceData, artefacts: Path, **options) -> Rig:
    """The recorded app and board, driven by the recording (the budgets as it had them)."""
    h = trace.header
    app = get_app(h.get("rig_file") or h["app"])
    try:
        recorded_plant = app.make_plant(**h.get("plant_options", {}))
    except (TypeError, ValueError, ArithmeticError):  # (a trace of a plant of one's own: the app's defaults)
        recorded_plant = app.make_plant()
    budgets = app.make_budgets(recorded_plant)
    plant = replay_plant(trace)
    return Rig(
        app,
        board=h["board"],
        seed=h["seed"],
        plant=plant,
        budgets=budgets,
        artefacts=artefacts,
        trace=True,
        record=True,
        **options,
    )


def first_difference(recorded: list, replayed: list) -> Difference | None:
    for i, (a, b) in enumerate(zip(recorded, replayed)):
        if tuple(a) != tuple(b):
            return Difference(i, min(a[0], b[0]), tuple(a), tuple(b))
    if len(recorded) == len(replayed):
        return None
    i = min(len(recorded), len(replayed))
    a = tuple(recorded[i]) if i < len(recorded) else None
    b = tuple(replayed[i]) if i < len(replayed) else None
    return Difference(i, (a or b)[0], a, b)
