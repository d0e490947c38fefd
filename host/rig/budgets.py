"""Timing budgets: named, measured quantities with a limit and statistics.

A period budget measures the time between successive events (a control step, a new
sonar sample) against its nominal period and tolerance. A latency budget measures how
long after a sample arrived the firmware first read it; a sample never read counts
as a miss. Values are microseconds of virtual time unless a budget says otherwise.
"""

import math


class Budget:
    def __init__(self, name: str, source: str, *, limit_us: int, description: str = ""):
        self.name = name
        self.source = source
        self.limit_us = limit_us
        self.description = description
        self.values: list[int] = []
        self.misses = 0

    def _record(self, value_us: int, missed: bool) -> None:
        self.values.append(value_us)
        if missed:
            self.misses += 1

    def stats(self) -> dict:
        values = sorted(self.values)
        return {
            "budget": self.name,
            "limit": self.limit_text(),
            "count": len(values),
            "p50": _percentile(values, 50),
            "p95": _percentile(values, 95),
            "p99": _percentile(values, 99),
            "max": values[-1] if values else None,
            "misses": self.misses,
        }

    def limit_text(self) -> str:
        return f"<= {self.limit_us} us"

    def check(self) -> None:
        """Raise AssertionError naming the budget if it was missed or never measured."""
        s = self.stats()
        if s["count"] == 0:
            raise AssertionError(f"budget {self.name}: expected measurements of {self.source}, got none")
        if self.misses:
            raise AssertionError(
                f"budget {self.name}: expected every value {self.limit_text()}, "
                f"got {self.misses} misses of {s['count']} (p50 {s['p50']}, p99 {s['p99']}, max {s['max']} us)"
            )


class PeriodBudget(Budget):
    """Time between successive events of ``source``: ``period_us`` +- ``tolerance_us``.
    For a UART source, ``marker`` makes an event of each received chunk that holds that
    byte (``b"$"``: the first byte of an NMEA sentence, sent at a fixed period, whereas
    its last byte moves with the sentence's length)."""

    def __init__(self, name, source, *, period_us: int, tolerance_us: int, description="",
                 marker: bytes | None = None):
        super().__init__(name, source, limit_us=period_us + tolerance_us, description=description)
        self.period_us = period_us
        self.tolerance_us = tolerance_us
        self.marker = marker
        self._last_us = None

    def counts(self, value) -> bool:
        """Whether a change of the source with this value is an event."""
        return self.marker is None or (isinstance(value, bytes) and self.marker in value)

    def event(self, t_us: int) -> None:
        if self._last_us is not None:
            dt = t_us - self._last_us
            self._record(dt, abs(dt - self.period_us) > self.tolerance_us)
        self._last_us = t_us

    def limit_text(self) -> str:
        return f"{self.period_us} +- {self.tolerance_us} us"


class LatencyBudget(Budget):
    """Delay from a new sample of ``source`` to the firmware's first read of it. For an
    ADC a sample is a new value; for a UART, a line (its last byte), read when the
    firmware's read takes that byte."""

    def __init__(self, name, source, *, limit_us: int, description=""):
        super().__init__(name, source, limit_us=limit_us, description=description)
        self._pending: dict[int, int] = {}

    def sample(self, sample_no: int, t_us: int) -> None:
        for old in [n for n in self._pending if n < sample_no]:  # superseded, never read
            self._record(t_us - self._pending.pop(old), True)
        self._pending[sample_no] = t_us

    def seen(self, sample_no: int, t_us: int) -> None:
        t_sample = self._pending.pop(sample_no, None)
        if t_sample is not None:
            latency = t_us - t_sample
            self._record(latency, latency > self.limit_us)


class PulseBudget(Budget):
    """Length of each pulse on actuator outputs: a pulse is the time while exactly one
    of ``sources`` is 1 (one track stopped, the other running). Both at 1 is a hold,
    not a pulse (the pool cleaner stops both tracks while it measures, and when done)."""

    def __init__(self, name, sources: tuple[str, ...], *, limit_us: int, description=""):
        super().__init__(name, sources[0], limit_us=limit_us, description=description)
        self.sources = tuple(sources)
        self._levels = dict.fromkeys(self.sources, 0)
        self._since_us = None

    def output(self, t_us: int, signal: str, value) -> None:
        self._levels[signal] = 1 if value else 0
        one = sum(self._levels.values()) == 1
        if one and self._since_us is None:
            self._since_us = t_us
        elif not one and self._since_us is not None:
            width = t_us - self._since_us
            self._since_us = None
            if width:  # releasing a hold one track at a time is no pulse
                self._record(width, width > self.limit_us)


class ComputeBudget(Budget):
    """Real (wall-clock) microseconds the firmware ran between two waits. Informational
    in lockstep runs: it is measured, never charged to virtual time."""

    def event(self, compute_us: int) -> None:
        self._record(compute_us, compute_us > self.limit_us)

    def limit_text(self) -> str:
        return f"<= {self.limit_us} us wall"


def _percentile(sorted_values: list[int], pct: float):
    if not sorted_values:
        return None
    k = max(0, math.ceil(pct / 100 * len(sorted_values)) - 1)
    return sorted_values[k]
