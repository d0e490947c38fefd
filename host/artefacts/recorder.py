"""What a run did, signal by signal, in virtual time.

A :class:`Recorder` keeps, in time order:

- every change of a plant output (what the firmware's inputs saw: encoder edges, ADC
  samples, bumper levels, UART bytes);
- every firmware output (the values the plant's inputs were set to, probe pins, pins
  wired to nothing);
- ground truth (the scalar fields of ``plant.truth()``) every ``truth_period_us``.

Speculative batches are rolled back with the plant (:meth:`Recorder.rewind`), so what
is kept is what the firmware really saw. Nothing here reads the wall clock: the same
run gives the same recording. :mod:`host.artefacts.folder` writes it out.
"""

import numbers

ROLE_SENSOR = "sensor"  # a plant output, read by the firmware
ROLE_ACTUATOR = "actuator"  # a firmware output that drives a plant input
ROLE_PROBE = "probe"  # a firmware output only the harness watches
ROLE_PIN = "pin"  # a firmware output wired to nothing
ROLES = (ROLE_SENSOR, ROLE_ACTUATOR, ROLE_PROBE, ROLE_PIN)

TRUTH_PERIOD_US = 50_000
"""Ground truth is sampled once per control quantum."""


class Recorder:
    def __init__(self, plant, *, truth_period_us: int = TRUTH_PERIOD_US):
        if truth_period_us <= 0:
            raise ValueError(f"truth_period_us: expected a positive period, got {truth_period_us!r}")
        self.truth_period_us = truth_period_us
        self.signals: dict[str, dict] = {}
        for name, kind in plant.outputs.items():
            self.signals[name] = {"role": ROLE_SENSOR, "kind": kind}
        for name, kind in plant.inputs.items():
            self.signals[name] = {"role": ROLE_ACTUATOR, "kind": kind}
        self.initial = {name: _plain(plant.output(name)) for name in plant.outputs}
        self.events: list[tuple[int, str, object]] = []
        self.truth: list[tuple[int, dict]] = []
        self._next_truth_us = 0
        self.sample(plant)

    def sensor(self, t_us: int, name: str, value) -> None:
        """A plant output changed (or took a new sample) at ``t_us``."""
        self.events.append((t_us, name, _plain(value)))

    def command(self, t_us: int, name: str, value, *, role: str = ROLE_ACTUATOR, kind: str = "level") -> None:
        """The firmware drove ``name`` to ``value`` at ``t_us``."""
        if name not in self.signals:
            self.signals[name] = {"role": role, "kind": kind}
        self.events.append((t_us, name, _plain(value)))

    @property
    def next_truth_us(self) -> int:
        """When the next ground-truth sample is due."""
        return self._next_truth_us

    def sample(self, plant) -> None:
        """Record ground truth if the plant has reached the next sample time."""
        t_us = plant.t_us
        if t_us < self._next_truth_us:
            return
        row = {k: _plain(v) for k, v in plant.truth().items() if isinstance(v, numbers.Real)}
        self.truth.append((t_us, row))
        self._next_truth_us = (t_us // self.truth_period_us + 1) * self.truth_period_us

    def rewind(self, t_us: int) -> None:
        """The plant went back to ``t_us``: forget what was recorded after it."""
        events, truth = self.events, self.truth
        while events and events[-1][0] > t_us:
            events.pop()
        while truth and truth[-1][0] > t_us:
            truth.pop()
        last = truth[-1][0] if truth else -1
        self._next_truth_us = (last // self.truth_period_us + 1) * self.truth_period_us

    def firmware_outputs(self) -> list[tuple[int, str, object]]:
        """What the firmware drove, in time order: what a replay compares."""
        kept = {name for name, info in self.signals.items() if info["role"] != ROLE_SENSOR}
        return [e for e in sorted(self.events, key=_time) if e[1] in kept]


def _time(event) -> int:
    return event[0]


def _plain(value):
    """Bytes as hex text, booleans and numpy scalars as Python numbers: what CSV and
    JSON hold."""
    if isinstance(value, bool):
        return int(value)
    if isinstance(value, (bytes, bytearray)):
        return bytes(value).hex()
    if hasattr(value, "item"):
        return value.item()
    return value
