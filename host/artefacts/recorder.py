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

Memory stays bounded however long the run: once the clock says nothing up to a time can
be rewound any more (:meth:`Recorder.commit`), and enough is kept, what was recorded up
to then goes in chunks to an unnamed temporary file (:class:`Spill`, gone once closed).
``events`` and ``truth`` read it all back; the folder's writers take it a chunk at a time
(``events_in_time_order``, ``iter_truth``).
"""

import numbers
import os
import pickle
import tempfile

ROLE_SENSOR = "sensor"  # a plant output, read by the firmware
ROLE_ACTUATOR = "actuator"  # a firmware output that drives a plant input
ROLE_PROBE = "probe"  # a firmware output only the harness watches
ROLE_PIN = "pin"  # a firmware output wired to nothing
ROLE_BUS = "bus"  # a bus's transactions, decoded as text (host/rig/hardware/bustrace.py)
ROLES = (ROLE_SENSOR, ROLE_ACTUATOR, ROLE_PROBE, ROLE_PIN, ROLE_BUS)

SENT = ":sent"
"""A line the firmware both reads and writes (a UART on a ``board_uart`` or a record link:
one plant signal both ways): what the firmware sends on it is recorded as ``<signal>:sent``,
so that a trace tells the plant's bytes to the firmware from the firmware's own."""

TRUTH_PERIOD_US = 50_000
"""Ground truth is sampled once per control quantum."""

SPILL_AT = 20_000
"""Events and truth rows kept in memory before the committed ones go to disk."""

STREAM_EVENTS, STREAM_ROWS = 64, 8
"""A turn of the streamed files (:meth:`Recorder.work`) once this many events or truth rows
wait for one (some of them may not be committed yet)."""


class Spill:
    """Lists of records appended in chunks to an unnamed temporary file (pickled), read
    back in order; nothing is left on disk once it is closed (or collected). Each reader
    reads at its own offsets (``os.pread``), so two can go through the file at once (the
    VCD writer reads the events twice, side by side)."""

    def __init__(self):
        self._file = None
        self._spans: list[tuple[int, int]] = []  # (offset, length) of each chunk

    def append(self, chunk: list) -> None:
        if self._file is None:
            self._file = tempfile.TemporaryFile(prefix="mpy-fil-rec-")
        data = pickle.dumps(chunk, protocol=pickle.HIGHEST_PROTOCOL)
        self._spans.append((self._file.tell(), len(data)))
        self._file.write(data)

    def chunks(self):
        f = self._file
        if f is None:
            return
        f.flush()
        fd = f.fileno()
        for offset, length in list(self._spans):
            yield pickle.loads(os.pread(fd, length, offset))

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None
            self._spans = []


class Recorder:
    def __init__(self, plant, *, truth_period_us: int = TRUTH_PERIOD_US):
        if truth_period_us <= 0:
            raise ValueError(f"truth_period_us: expected a positive period, got {truth_period_us!r}")
        self.truth_period_us = truth_period_us
        self.signals: dict[str, dict] = {}
        for name, kind in plant.outputs.items():
            self.signals[name] = {"role": ROLE_SENSOR, "kind": kind}
        self._sent: dict[str, str] = {}  # a two-way line -> the name what the firmware sends on it is recorded as
        for name, kind in plant.inputs.items():
            if name in plant.outputs:
                self._sent[name] = name + SENT
                name += SENT
            self.signals[name] = {"role": ROLE_ACTUATOR, "kind": kind}
        self.initial = {name: _plain(plant.output(name)) for name in plant.outputs}
        self._events: list[tuple[int, str, object]] = []  # not yet spilled
        self._truth: list[tuple[int, dict]] = []
        self._spilled_events = Spill()
        self._spilled_truth = Spill()
        self._last_event_us = -1  # of the last event spilled
        self._truth_spilled_to_us = -1  # of the last truth row spilled
        self._spilled_columns: dict[str, None] = {}  # the truth columns of the rows spilled, in order
        self.sorted = True  # so far, every event came at or after the time of the one before
        self.events_spilled = self.rows_spilled = 0  # records gone to disk
        self.committed_us = -1  # nothing before this time can be rewound (the clock's last commit)
        self.streamed = None  # host.artefacts.streaming.Streamed: the folder's files made as the run goes
        self._next_truth_us = 0
        self.sample(plant)

    @property
    def events(self) -> list[tuple[int, str, object]]:
        """Every recorded (t_us, name, value), in the order recorded."""
        return [e for chunk in self._iter_events() for e in chunk]

    @property
    def truth(self) -> list[tuple[int, dict]]:
        """Every ground-truth sample (t_us, {column: value}), in time order."""
        return [row for chunk in self.iter_truth() for row in chunk]

    def _iter_events(self):
        yield from self._spilled_events.chunks()
        yield self._events

    def iter_truth(self):
        """The ground-truth samples in chunks (lists), in time order."""
        yield from self._spilled_truth.chunks()
        yield self._truth

    def truth_columns(self) -> list[str]:
        """The ground truth's columns (``t_us`` aside), in the order they first came: those of
        the rows spilled were noted as they went, so nothing is read back from disk."""
        columns = dict(self._spilled_columns)
        _note_columns(columns, self._truth)
        return list(columns)

    def sensor(self, t_us: int, name: str, value) -> None:
        """A plant output changed (or took a new sample) at ``t_us``."""
        self._events.append((t_us, name, _plain(value)))

    def command(self, t_us: int, name: str, value, *, role: str = ROLE_ACTUATOR, kind: str = "level") -> None:
        """The firmware drove ``name`` to ``value`` at ``t_us``."""
        name = self._sent.get(name, name)
        if name not in self.signals:
            self.signals[name] = {"role": role, "kind": kind}
        self._events.append((t_us, name, _plain(value)))

    @property
    def next_truth_us(self) -> int:
        """When the next ground-truth sample is due."""
        return self._next_truth_us

    def sample(self, plant) -> None:
        """Record ground truth if the plant has reached the next sample time."""
        t_us = plant.t_us
        if t_us < self._next_truth_us:
            return
        row = {}
        for k, v in plant.truth().items():  # (the scalars: a number as CSV and JSON hold it)
            kind = type(v)
            if kind is float or kind is int:  # (_PLAIN_NUMBERS, without a set's look-up)
                row[k] = v
            elif kind is bool:
                row[k] = int(v)
            elif kind not in _NOT_REAL and isinstance(v, numbers.Real):
                row[k] = _plain(v)
        self._truth.append((t_us, row))
        self._next_truth_us = (t_us // self.truth_period_us + 1) * self.truth_period_us

    def rewind(self, t_us: int) -> None:
        """The plant went back to ``t_us``: forget what was recorded after it (never what
        was spilled: that was committed)."""
        if self.streamed is not None:
            self.streamed.rewound(t_us)
        events, truth = self._events, self._truth
        while events and events[-1][0] > t_us:
            events.pop()
        while truth and truth[-1][0] > t_us:
            truth.pop()
        last = truth[-1][0] if truth else self._truth_spilled_to_us
        self._next_truth_us = (last // self.truth_period_us + 1) * self.truth_period_us

    def commit(self, t_us: int) -> None:
        """Nothing up to ``t_us`` will be rewound: once enough is kept, what is before
        then goes to disk (what is at ``t_us`` may still be joined by more at that instant),
        made into the folder's lines first when they are streamed."""
        if t_us > self.committed_us:
            self.committed_us = t_us
        if len(self._events) + len(self._truth) < SPILL_AT:
            return
        if self.streamed is not None:
            self.streamed.work(t_us, bounded=False)
        n = _prefix(self._events, t_us)
        if n:
            self._check_order(self._events[:n])
            self._spilled_events.append(self._events[:n])
            self._events = self._events[n:]
            self.events_spilled += n
        n = _prefix(self._truth, t_us)
        if n:
            self._truth_spilled_to_us = self._truth[n - 1][0]
            _note_columns(self._spilled_columns, self._truth[:n])
            self._spilled_truth.append(self._truth[:n])
            self._truth = self._truth[n:]
            self.rows_spilled += n

    def work(self) -> None:
        """A turn of the folder's streamed files (while the firmware works on a STATE), once
        enough records wait for one (a turn's own cost, spread over them)."""
        streamed = self.streamed
        if streamed is not None and (
            len(self._events) + self.events_spilled - streamed.events_done >= STREAM_EVENTS
            or len(self._truth) + self.rows_spilled - streamed.rows_done >= STREAM_ROWS
        ):
            streamed.work()

    def _check_order(self, events: list) -> None:
        last = self._last_event_us
        for t, _name, _value in events:
            if t < last:
                self.sorted = False  # (real time: an output stamped before an input)
            last = t
        self._last_event_us = last

    def events_in_time_order(self):
        """The events sorted by time (stable: in the order recorded within a
        microsecond), one by one: read back from disk as they go when they were recorded
        in time order (lockstep always records them so), else sorted in memory."""
        last = self._last_event_us
        in_order = self.sorted and all(e[0] >= last for e in self._events[:1])
        in_order = in_order and all(a[0] <= b[0] for a, b in zip(self._events, self._events[1:]))
        if not in_order:
            yield from sorted(self.events, key=_time)
            return
        for chunk in self._iter_events():
            yield from chunk

    def firmware_outputs(self) -> list[tuple[int, str, object]]:
        """What the firmware drove, in time order: what a replay compares."""
        kept = {name for name, info in self.signals.items() if info["role"] != ROLE_SENSOR}
        return [e for e in self.events_in_time_order() if e[1] in kept]

    def close(self) -> None:
        """Drop what went to disk (the temporary files)."""
        self._spilled_events.close()
        self._spilled_truth.close()
        if self.streamed is not None:
            self.streamed.close()


def _note_columns(columns: dict, rows: list) -> None:
    """Add to ``columns`` (an ordered set) each key of ``rows`` not in it, ``t_us`` aside."""
    seen = columns.keys() | {"t_us"}
    for _t, row in rows:
        if row.keys() <= seen:
            continue
        for key in row:
            if key not in seen:
                seen.add(key)
                columns[key] = None


def _prefix(records: list, t_us: int) -> int:
    """How many records from the start are before ``t_us``."""
    n = 0
    for record in records:
        if record[0] >= t_us:
            break
        n += 1
    return n


def _time(event) -> int:
    return event[0]


_PLAIN_NUMBERS = {int, float}  # (the usual truth values: as they are, with no ABC check)
_NOT_REAL = {tuple, list, dict, str, bytes, bytearray, type(None)}  # (left out, with no ABC check)


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
