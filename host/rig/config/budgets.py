"""Timing budgets: named, measured quantities with a limit and statistics.

A period budget measures the time between successive events (a control step, a new
sonar sample) against its nominal period and tolerance. A latency budget measures how
long after a sample arrived the firmware first read it; a sample never read counts
as a miss. Values are microseconds of virtual time unless a budget says otherwise.

A budget says what it listens to with :meth:`Budget.hooks`: ``(event, signal, callable)``
triples the rig calls as the run goes. The events:

==============  =============================================  =============================
event           when                                           call
==============  =============================================  =============================
``CHANGE``      a plant output changed (or took a sample)      ``f(t_us, value)``
``SAMPLE``      a new sample reached a firmware ADC or UART    ``f(t_us, sample_no)``
``SEEN``        the firmware first read that sample            ``f(t_us, sample_no)``
``LEVEL``       the firmware drove a pin to a level            ``f(t_us, signal, value, changed)``
``COMPUTE``     the firmware blocked after running             ``f(compute_us)`` (signal None)
``BUS``         a transfer on a bus (the signal: its name)     ``f(transaction)``
==============  =============================================  =============================

``CHANGE`` and ``SAMPLE`` come from speculative plant batches: the rig holds them back
until the firmware has moved past their time, so a rolled-back batch never reaches a
budget. ``docs/budgets.md`` lists the apps' budgets.

A budget keeps its values as a histogram: each distinct value (integer microseconds)
with how many times it was measured. Count, min, max, misses and the percentiles are
exact (the same numbers a list of every value gives), and the memory is bounded by the
number of distinct values, not by the length of the run: a 50 ms period measured for
a day in lockstep holds one or two entries, not 1.7 million values.
"""

import math

CHANGE = "change"
SAMPLE = "sample"
SEEN = "seen"
LEVEL = "level"
COMPUTE = "compute"
BUS = "bus"
EVENTS = (CHANGE, SAMPLE, SEEN, LEVEL, COMPUTE, BUS)


MAX_BUDGET_US = 3_600_000_000  # a rig file's budget times: at most an hour
FIRST_MISSES = 5  # misses a budget's failure message names, with their times
KEPT_MISSES = 1000  # misses a budget keeps the time of (budgets.json, the VCD's events)


class Budget:
    """A budget of a rig file (``[budgets.<name>]``, docs/rig-file.md) declares its own
    schema: its ``kind``, the keys it takes with their types, which of them a rig file
    may leave out and the bounds of its times; ``host/rig/config/rigfile.py`` checks a
    table against them (:meth:`rig_keys`, :data:`BOUNDS`)."""

    wall_clock = False
    """True for a budget measured in wall-clock time (informational in lockstep runs)."""
    KIND: str | None = None
    """Its ``kind`` in a rig file (None: made in code only)."""
    KEYS: dict = {}
    """The keys a rig file's table of this kind takes, with their types, beside ``kind`` and
    ``description`` (:data:`COMMON_KEYS`)."""
    OPTIONAL: tuple[str, ...] = ()
    """Those of :data:`KEYS` a rig file may leave out: each then has the class's default
    (a period budget's ``period_us``: the sample period of the plant's signal)."""
    ON_BUS = False
    """A bus budget: its ``source`` is a bus of the plant's devices, not a signal."""
    PERIOD_FROM_PLANT = False
    """Without ``period_us``, the period is the sample period of the plant's ``source``."""
    BOUNDS = {"period_us": (1, MAX_BUDGET_US), "limit_us": (1, MAX_BUDGET_US), "tolerance_us": (0, MAX_BUDGET_US)}
    """The least and most microseconds each time key takes."""
    COMMON_KEYS = {"kind": str, "description": str}

    @classmethod
    def rig_keys(cls, table: dict) -> tuple[dict, tuple[str, ...]]:
        """(the keys with their types, the required ones) of a rig file's ``table``."""
        return {**cls.COMMON_KEYS, **cls.KEYS}, tuple(k for k in cls.KEYS if k not in cls.OPTIONAL)

    def __init__(self, name: str, source: str, *, limit_us: int, description: str = ""):
        self.name = name
        self.source = source
        self.limit_us = limit_us
        self.description = description
        self.histogram: dict[int, int] = {}
        """value (us) -> how many times it was measured"""
        self.count = 0
        self.misses = 0
        self.first_misses: list[tuple] = []  # (virtual t_us or None, value) of the first KEPT_MISSES
        self.checked: str | None = None
        """None until the test calls :meth:`check`; then "held" or "missed" (what it found)."""
        self.tolerated = ""
        """Why the test tolerates this budget's misses (:meth:`tolerate`); "" when it does not."""
        self.replaced = 0
        """Misses that are samples replaced before the firmware read them (a latency budget's)."""

    def hooks(self) -> list[tuple]:
        """``(event, signal, callable)`` for each event this budget measures."""
        return []

    def _record(self, value_us: int, missed: bool, t_us: int | None = None) -> None:
        histogram = self.histogram
        histogram[value_us] = histogram.get(value_us, 0) + 1
        self.count += 1
        if missed:
            self.misses += 1
            if len(self.first_misses) < KEPT_MISSES:
                self.first_misses.append((t_us, value_us))

    @property
    def values(self) -> list[int]:
        """Every measured value, in ascending order (the order of arrival is not kept).
        Built from the histogram on each call: the whole run's length in memory, so
        meant for short runs and tests; ``stats()`` and ``histogram`` stay small."""
        return [value for value, n in sorted(self.histogram.items()) for _ in range(n)]

    def stats(self) -> dict:
        ranked = sorted(self.histogram.items())
        return {
            "budget": self.name,
            "limit": self.limit_text(),
            "count": self.count,
            "p50": _percentile(ranked, self.count, 50),
            "p95": _percentile(ranked, self.count, 95),
            "p99": _percentile(ranked, self.count, 99),
            "min": ranked[0][0] if ranked else None,
            "max": ranked[-1][0] if ranked else None,
            "misses": self.misses,
        }

    def record(self) -> dict:
        """Everything about this budget, for ``budgets.json`` in a trace folder."""
        return {
            "name": self.name,
            "type": type(self).__name__,
            "source": self.source,
            "description": self.description,
            "limit": self.limit_text(),
            "limit_us": self.limit_us,
            "wall_clock": self.wall_clock,
            "stats": self.stats(),
            "histogram_us": [[value, n] for value, n in sorted(self.histogram.items())],
            "misses_at": [[t, value] for t, value in self.first_misses],  # the first KEPT_MISSES
            "replaced": self.replaced,
        }

    def limit_text(self) -> str:
        return f"<= {self.limit_us} us"

    def tolerate(self, why: str) -> "Budget":
        """The test allows this budget's misses, for the reason ``why`` (said wherever
        the budget's verdict is shown: ``tolerated``, never red); :meth:`check` then
        only asks for measurements."""
        if not why or not why.strip():
            raise ValueError(f"budget {self.name}: tolerate() needs the reason the misses are allowed")
        self.tolerated = why.strip()
        return self

    def judgement(self) -> dict:
        """What the test made of this budget, for its verdict (:mod:`host.rig.config.verdicts`)."""
        return {
            "checked": self.checked,
            "tolerated": self.tolerated,
            "replaced": self.replaced,
            "wall_clock": self.wall_clock,
        }

    def check(self) -> None:
        """Raise AssertionError naming the budget if it was missed or never measured
        (misses the test tolerates aside: :meth:`tolerate`)."""
        s = self.stats()
        self.checked = "missed"
        if s["count"] == 0:
            raise AssertionError(f"budget {self.name}: expected measurements of {self.source}, got none")
        if self.misses and not self.tolerated:
            first = ", ".join(
                f"{value} us" + (f" at virtual t={t / 1e6:.6f} s" if t is not None else "")
                for t, value in self.first_misses[:FIRST_MISSES]
            )
            raise AssertionError(
                f"budget {self.name}: expected every value {self.limit_text()}, "
                f"got {self.misses} misses of {s['count']} (p50 {s['p50']}, p99 {s['p99']}, max {s['max']} us); "
                f"the first: {first}"
            )
        self.checked = "held"


class PeriodBudget(Budget):
    """Time between successive events of ``source``: ``period_us`` +- ``tolerance_us``.
    An event is a change of a plant output (a new sample), or a toggle of a pin the
    firmware drives (a probe). For a UART source, ``marker`` makes an event of each
    received chunk that holds that byte (``b"$"``: the first byte of an NMEA sentence,
    sent at a fixed period, whereas its last byte moves with the sentence's length)."""

    KIND = "period"
    KEYS = {"source": str, "period_us": int, "tolerance_us": int, "marker": str}
    OPTIONAL = ("marker", "period_us")
    PERIOD_FROM_PLANT = True

    def __init__(self, name, source, *, period_us: int, tolerance_us: int, description="", marker: bytes | None = None):
        super().__init__(name, source, limit_us=period_us + tolerance_us, description=description)
        self.period_us = period_us
        self.tolerance_us = tolerance_us
        self.marker = marker
        self._last_us = None

    def hooks(self) -> list[tuple]:
        return [(CHANGE, self.source, self.on_change), (LEVEL, self.source, self.on_level)]

    def counts(self, value) -> bool:
        """Whether a change of the source with this value is an event."""
        return self.marker is None or (isinstance(value, bytes) and self.marker in value)

    def on_change(self, t_us: int, value) -> None:
        if self.counts(value):
            self.event(t_us)

    def on_level(self, t_us: int, _signal: str, _value, changed: bool) -> None:
        if changed:
            self.event(t_us)

    def event(self, t_us: int) -> None:
        if self._last_us is not None:
            dt = t_us - self._last_us
            self._record(dt, abs(dt - self.period_us) > self.tolerance_us, t_us)
        self._last_us = t_us

    def limit_text(self) -> str:
        return f"{self.period_us} +- {self.tolerance_us} us"

    def record(self) -> dict:
        return {**super().record(), "period_us": self.period_us, "tolerance_us": self.tolerance_us}


class LatencyBudget(Budget):
    """Delay from a new sample of ``source`` to the firmware's first read of it. For an
    ADC a sample is a new value; for a UART, a line (its last byte), read when the
    firmware's read takes that byte."""

    KIND = "latency"
    KEYS = {"source": str, "limit_us": int}

    def __init__(self, name, source, *, limit_us: int, description=""):
        super().__init__(name, source, limit_us=limit_us, description=description)
        self._pending: dict[int, int] = {}

    def hooks(self) -> list[tuple]:
        return [(SAMPLE, self.source, self.sample), (SEEN, self.source, self.seen)]

    def sample(self, t_us: int, sample_no: int) -> None:
        for old in [n for n in self._pending if n < sample_no]:  # superseded, never read
            self.replaced += 1
            self._record(t_us - self._pending.pop(old), True, t_us)
        self._pending[sample_no] = t_us

    def seen(self, t_us: int, sample_no: int) -> None:
        t_sample = self._pending.pop(sample_no, None)
        if t_sample is not None:
            latency = t_us - t_sample
            self._record(latency, latency > self.limit_us, t_us)

    def record(self) -> dict:
        return {**super().record(), "period_us": None}


class PulseBudget(Budget):
    """Length of each pulse on actuator outputs: a pulse is the time while exactly one
    of ``sources`` is 1 (one track stopped, the other running). Both at 1 is a hold,
    not a pulse (the pool cleaner stops both tracks while it measures, and when done)."""

    KIND = "pulse"
    KEYS = {"sources": list, "limit_us": int}

    def __init__(self, name, sources: tuple[str, ...], *, limit_us: int, description=""):
        super().__init__(name, sources[0], limit_us=limit_us, description=description)
        self.sources = tuple(sources)
        self._levels = dict.fromkeys(self.sources, 0)
        self._since_us = None

    def hooks(self) -> list[tuple]:
        return [(LEVEL, source, self.on_level) for source in self.sources]

    def on_level(self, t_us: int, signal: str, value, _changed: bool) -> None:
        self.output(t_us, signal, value)

    def output(self, t_us: int, signal: str, value) -> None:
        self._levels[signal] = 1 if value else 0
        one = sum(self._levels.values()) == 1
        if one and self._since_us is None:
            self._since_us = t_us
        elif not one and self._since_us is not None:
            width = t_us - self._since_us
            self._since_us = None
            if width:  # releasing a hold one track at a time is no pulse
                self._record(width, width > self.limit_us, t_us)


class ComputeBudget(Budget):
    """Real (wall-clock) microseconds the firmware ran between two waits. Informational
    in lockstep runs: it is measured, never charged to virtual time. With MCU time
    (``[board] cpu``, docs/mcu-time.md, ``mcu`` set by the rig) the board CPU's
    microseconds the main program computed between two waits, charged to virtual time."""

    KIND = "compute"
    KEYS = {"limit_us": int}
    mcu = None  # the board CPU whose time the firmware reports (None: wall time)

    @property
    def wall_clock(self) -> bool:
        return self.mcu is None

    def hooks(self) -> list[tuple]:
        return [(COMPUTE, None, self.event)]

    def event(self, compute_us: int) -> None:
        self._record(compute_us, compute_us > self.limit_us)

    def limit_text(self) -> str:
        return f"<= {self.limit_us} us " + ("wall" if self.mcu is None else f"on {self.mcu}")


class BusLatencyBudget(Budget):
    """How long each transfer on the bus ``source`` takes at its clock (to ``address``
    only, when given): a transfer longer than ``limit_us`` is a miss. A stuck bus's
    transfer (its timeout, which the host is not told) is a miss of ``limit_us + 1``."""

    KIND = "bus_latency"
    KEYS = {"source": str, "limit_us": int, "address": int}
    OPTIONAL = ("address",)
    ON_BUS = True

    def __init__(self, name, source, *, limit_us: int, address: int | None = None, description=""):
        super().__init__(name, source, limit_us=limit_us, description=description)
        self.address = address

    def hooks(self) -> list[tuple]:
        return [(BUS, self.source, self.transfer)]

    def transfer(self, tx) -> None:
        if self.address is not None and tx.address != self.address:
            return
        took = self.limit_us + 1 if tx.duration_us is None else tx.duration_us
        self._record(took, took > self.limit_us, tx.t_us)

    def record(self) -> dict:
        return {**super().record(), "address": self.address}


class BusSampleBudget(PeriodBudget):
    """A sensor's sample period read over a bus: the time between successive reads of
    the data registers from ``register`` of the device at ``address`` on the bus
    ``source`` (``period_us`` +- ``tolerance_us``). With ``ready`` (the device's
    data-ready output, ``imu.int1``), the time from its rise to the next such read
    instead, against ``limit_us``; a sample ready again before it was read is a miss."""

    KIND = "bus_sample"
    KEYS = {"source": str, "register": int, "address": int, "period_us": int, "tolerance_us": int, "ready": str}
    KEYS |= {"limit_us": int}
    ON_BUS = True
    OPTIONAL = ("address", "ready", "limit_us")  # (without ready: its period_us and tolerance_us)
    OPTIONAL_READY = ("address", "period_us", "tolerance_us", "ready")  # (with ready: its limit_us)
    PERIOD_FROM_PLANT = False

    @classmethod
    def rig_keys(cls, table: dict) -> tuple[dict, tuple[str, ...]]:
        """With ``ready``: its ``limit_us``; without: its ``period_us`` and ``tolerance_us``."""
        optional = cls.OPTIONAL_READY if "ready" in table else cls.OPTIONAL
        return {**cls.COMMON_KEYS, **cls.KEYS}, tuple(k for k in cls.KEYS if k not in optional)

    def __init__(
        self,
        name,
        source,
        *,
        register: int,
        address: int | None = None,
        period_us: int = 0,
        tolerance_us: int = 0,
        ready: str | None = None,
        limit_us: int = 0,
        description="",
    ):
        super().__init__(name, source, period_us=period_us, tolerance_us=tolerance_us, description=description)
        if ready is not None:
            self.limit_us = limit_us
        self.address, self.register, self.ready = address, register, ready
        self._ready_us = None

    def hooks(self) -> list[tuple]:
        hooks = [(BUS, self.source, self.transfer)]
        return hooks + [(CHANGE, self.ready, self.on_ready)] if self.ready else hooks

    def transfer(self, tx) -> None:
        if not tx.reads or tx.register != self.register:
            return
        if self.address is not None and tx.address != self.address:
            return
        if self.ready is None:
            self.event(tx.t_us)
        elif self._ready_us is not None:
            waited = tx.t_us - self._ready_us
            self._record(waited, waited > self.limit_us, tx.t_us)
            self._ready_us = None

    def on_ready(self, t_us: int, value) -> None:
        if not value:
            return
        if self._ready_us is not None:  # (the sample before was never read)
            self.replaced += 1
            self._record(t_us - self._ready_us, True, t_us)
        self._ready_us = t_us

    def limit_text(self) -> str:
        return f"<= {self.limit_us} us from {self.ready}" if self.ready else super().limit_text()

    def record(self) -> dict:
        return {**super().record(), "address": self.address, "register": self.register, "ready": self.ready}


class ReactionBudget(Budget):
    """Across boards (a rig file with ``[[boards]]``: docs/multi-board.md): the time from
    an event on one board (``stimulus``: it drives the pin wired to that signal to a new
    level) to the next event on another (``response``), at most ``limit_us`` (a command sent
    on one and acted on by the other). A stimulus while one waits for its response is part
    of it (the first one times it); one never answered by the run's end counts as a miss
    once it is older than the limit. The set of boards hooks it to both boards' outputs."""

    def __init__(self, name, stimulus: tuple[str, str], response: tuple[str, str], *, limit_us: int, description=""):
        super().__init__(name, f"{stimulus[0]}:{stimulus[1]}", limit_us=limit_us, description=description)
        self.stimulus, self.response = stimulus, response
        self._pending_us = None

    def on_stimulus(self, t_us: int, _signal: str, _value, changed: bool) -> None:
        if changed and self._pending_us is None:
            self._pending_us = t_us

    def on_response(self, t_us: int, _signal: str, _value, changed: bool) -> None:
        if changed and self._pending_us is not None:
            latency = t_us - self._pending_us
            self._pending_us = None
            self._record(latency, latency > self.limit_us, t_us)

    def end(self, t_us: int) -> None:
        """The run ends at ``t_us``: a stimulus still unanswered past the limit is a miss."""
        if self._pending_us is not None and t_us - self._pending_us > self.limit_us:
            self._record(t_us - self._pending_us, True, t_us)
            self._pending_us = None

    def limit_text(self) -> str:
        return f"{self.stimulus[0]}:{self.stimulus[1]} -> {self.response[0]}:{self.response[1]} <= {self.limit_us} us"

    def record(self) -> dict:
        return {**super().record(), "stimulus": list(self.stimulus), "response": list(self.response)}


KINDS = {
    cls.KIND: cls
    for cls in (PeriodBudget, LatencyBudget, PulseBudget, ComputeBudget, BusLatencyBudget, BusSampleBudget)
}
"""The budgets a rig file names by ``kind``, each with its schema."""


class BudgetHooks:
    """The budgets' hooks by event and signal, as the rig calls them: ``change[signal]``
    is the list of callables for a change of that signal, and so on."""

    def __init__(self, budgets):
        self.change: dict[str, list] = {}
        self.sample: dict[str, list] = {}
        self.seen: dict[str, list] = {}
        self.level: dict[str, list] = {}
        self.bus: dict[str, list] = {}
        self.compute: list = []
        for budget in budgets:
            for event, signal, call in budget.hooks():
                if event not in EVENTS:
                    raise ValueError(f"budget {budget.name}: unknown event {event!r} (events: {', '.join(EVENTS)})")
                if event == COMPUTE:
                    self.compute.append(call)
                else:
                    getattr(self, event).setdefault(signal, []).append(call)


def _percentile(ranked: list[tuple[int, int]], count: int, pct: float):
    """The value of rank ceil(pct% of count) (nearest rank) in ``ranked``, the histogram's
    (value, n) pairs in ascending order of value: what indexing the sorted list of every
    value gives."""
    if not count:
        return None
    k = max(0, math.ceil(pct / 100 * count) - 1)
    seen = 0
    for value, n in ranked:
        seen += n
        if seen > k:
            return value
    raise ValueError(f"histogram holds {seen} values, expected {count}")
