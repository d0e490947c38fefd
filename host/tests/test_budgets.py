"""Timing budgets that the pool cleaner added: sentence periods on a UART (counted at a
marker byte) and track-stop pulses (one of two outputs at 1); statistics kept as a
histogram in bounded memory, exactly as a list of every value gives them."""

import math
import random
import sys

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from host.rig.config.budgets import COMPUTE, LEVEL, Budget, BudgetHooks, PeriodBudget, PulseBudget


def test_a_uart_period_counts_chunks_with_the_marker_byte_only():
    budget = PeriodBudget("sonar.period", "sonar.uart", period_us=500_000, tolerance_us=1_000, marker=b"$")
    events = [(102_083, b"$"), (104_166, b"S"), (139_583, b"\r\n"), (602_083, b"$SDD"), (1_102_083, b"$")]
    for t, chunk in events:
        if budget.counts(chunk):
            budget.event(t)
    assert budget.histogram == {500_000: 2} and budget.misses == 0
    assert PeriodBudget("p", "adc", period_us=1, tolerance_us=0).counts(123), "no marker: every change counts"


def test_a_stop_pulse_is_the_time_one_track_alone_is_stopped():
    budget = PulseBudget("track.stop", ("track_l.stop", "track_r.stop"), limit_us=300_000)
    budget.output(0, "track_l.stop", 1)  # both held at start: a hold, not a pulse
    budget.output(0, "track_r.stop", 1)
    budget.output(5_000_000, "track_l.stop", 0)  # released one at a time: no pulse either
    budget.output(5_000_000, "track_r.stop", 0)
    budget.output(6_000_000, "track_r.stop", 1)
    budget.output(6_250_000, "track_r.stop", 0)
    budget.output(7_000_000, "track_l.stop", 1)
    budget.output(7_350_000, "track_l.stop", 0)
    budget.output(8_000_000, "track_l.stop", 1)
    budget.output(8_100_000, "track_r.stop", 1)  # both stopped (done): the pulse ends
    assert budget.values == [100_000, 250_000, 350_000] and budget.misses == 1  # in ascending order


class EdgeCount(Budget):
    """A budget kind the rig has never heard of: it counts what its hooks are given."""

    def __init__(self):
        super().__init__("edges", "probe:control", limit_us=0)
        self.calls = []

    def hooks(self):
        return [(LEVEL, self.source, lambda *a: self.calls.append(("level", *a))), (COMPUTE, None, self.calls.append)]


def test_budget_hooks_index_each_budget_by_event_and_signal():
    period = PeriodBudget("sonar.period", "sonar.adc", period_us=500_000, tolerance_us=1_000)
    custom = EdgeCount()
    hooks = BudgetHooks([period, custom])
    assert hooks.change == {"sonar.adc": [period.on_change]}
    assert hooks.level["sonar.adc"] == [period.on_level] and hooks.compute == [custom.calls.append]
    for call in hooks.change["sonar.adc"]:
        call(20_000, 4000)
        call(520_000, 4100)
    assert period.histogram == {500_000: 1}


def test_a_hook_on_an_unknown_event_is_refused_by_name():
    class Odd(Budget):
        def hooks(self):
            return [("tick", "x", print)]

    with pytest.raises(ValueError, match="budget odd: unknown event 'tick'"):
        BudgetHooks([Odd("odd", "x", limit_us=1)])


# -- statistics in bounded memory: a histogram gives what the list of every value gave ----


def list_stats(values: list[int], misses: int) -> dict:
    """The statistics as budgets computed them when they kept every value in a list
    (nearest-rank percentiles of the sorted list): the reference the histogram must match."""
    ranked = sorted(values)

    def pct(p):
        return ranked[max(0, math.ceil(p / 100 * len(ranked)) - 1)] if ranked else None

    return {
        "count": len(ranked),
        "p50": pct(50),
        "p95": pct(95),
        "p99": pct(99),
        "min": ranked[0] if ranked else None,
        "max": ranked[-1] if ranked else None,
        "misses": misses,
    }


measurements = st.lists(st.tuples(st.integers(-(2**40), 2**40), st.booleans()), max_size=300)
clustered = st.lists(st.tuples(st.integers(49_000, 51_000), st.booleans()), max_size=300)


@settings(max_examples=300, derandomize=True, database=None, deadline=None)
@given(st.one_of(measurements, clustered))
def test_histogram_statistics_are_the_ones_a_list_of_every_value_gives(measured):
    budget = Budget("b", "x", limit_us=50_000)
    for value, missed in measured:
        budget._record(value, missed)
    values = [v for v, _ in measured]
    stats = budget.stats()
    expected = list_stats(values, sum(m for _, m in measured))
    assert {k: stats[k] for k in expected} == expected, f"histogram {budget.histogram}, values {values}"
    assert budget.values == sorted(values) and budget.count == len(values)
    record = budget.record()
    assert [v for v, n in record["histogram_us"] for _ in range(n)] == sorted(values), record
    assert record["stats"] == stats


def deep_size(obj, seen=None) -> int:
    """Bytes an object holds, following dicts, lists, tuples and an instance's attributes."""
    seen = set() if seen is None else seen
    if id(obj) in seen:
        return 0
    seen.add(id(obj))
    size = sys.getsizeof(obj)
    if isinstance(obj, dict):
        size += sum(deep_size(k, seen) + deep_size(v, seen) for k, v in obj.items())
    elif isinstance(obj, (list, tuple, set)):
        size += sum(deep_size(v, seen) for v in obj)
    elif hasattr(obj, "__dict__"):
        size += deep_size(vars(obj), seen)
    return size


def test_a_period_budget_measured_two_million_times_holds_no_more_than_its_distinct_values():
    """A day of 50 ms control steps with up to 200 us of jitter (1.7 million values): the
    budget's memory stops growing once every distinct value has been seen."""
    budget = PeriodBudget("control.period", "probe:control", period_us=50_000, tolerance_us=100)
    rng = random.Random(13)
    jitter = [rng.randrange(-100, 101) for _ in range(4096)]
    t = 0
    sizes = []
    for i in range(2_000_000):
        t += 50_000 + jitter[i & 4095]
        budget.event(t)
        if i in (200_000, 1_999_999):
            sizes.append(deep_size(budget))
    stats = budget.stats()
    assert stats["count"] == 1_999_999 and len(budget.histogram) <= 201, (stats, len(budget.histogram))
    assert stats["min"] >= 49_800 and stats["max"] <= 50_200, stats
    assert sizes[1] == sizes[0] < 64_000, f"budget's memory after 200 000 and 2 000 000 values: {sizes} bytes"


def test_the_timing_plot_counts_the_same_from_a_histogram_as_from_every_value():
    """budgets.json holds ``histogram_us``; a trace folder from before holds ``values_us``:
    the timing plot's bars are the same either way."""
    import numpy as np

    from host.report.plots import budget_values

    rng = random.Random(5)
    values = [rng.choice([50_000, 50_000, 49_990, 51_200]) for _ in range(500)]
    budget = Budget("control.period", "probe:control", limit_us=51_000)
    for v in values:
        budget._record(v, v > 51_000)
    new_values, new_counts = budget_values(budget.record())
    old_values, old_counts = budget_values({"values_us": values})
    bins = np.linspace(49_000, 52_000, 41)
    assert list(new_counts) == [budget.histogram[v] for v in sorted(budget.histogram)]
    assert np.array_equal(
        np.histogram(new_values, bins, weights=new_counts)[0], np.histogram(old_values, bins, weights=old_counts)[0]
    ), "the timing plot's bars differ between a budgets.json with histogram_us and one with values_us"


def test_a_failed_budget_says_when_its_first_misses_happened():
    period = PeriodBudget("control.period", "probe:control", period_us=50_000, tolerance_us=1_000)
    for t in (0, 50_000, 100_000, 153_000, 203_000, 260_000):  # late at 153 ms and at 260 ms
        period.on_change(t, 1)
    with pytest.raises(AssertionError) as err:
        period.check()
    text = str(err.value)
    assert "2 misses of 5" in text, text
    assert "the first: 53000 us at virtual t=0.153000 s, 57000 us at virtual t=0.260000 s" in text, text


def test_each_budget_kind_declares_its_own_rig_file_schema():
    """A budget of a rig file declares its ``kind``, keys, optional keys and bounds on its
    class (host/rig/config/budgets.py); the rig file's reader holds no table of its own."""
    from host.rig.config import budgets, rigfile

    assert list(budgets.KINDS) == ["period", "latency", "pulse", "compute", "bus_latency", "bus_sample"]
    for kind, cls in budgets.KINDS.items():
        keys, required = cls.rig_keys({})
        assert cls.KIND == kind and {"kind", "description"} <= set(keys), f"{cls.__name__}: expected kind {kind}"
        assert set(required) <= set(cls.KEYS) and set(cls.OPTIONAL) <= set(cls.KEYS), f"{cls.__name__}: {required}"
    assert budgets.KINDS["bus_sample"].rig_keys({"ready": "imu.int1"})[1] == ("source", "register", "limit_us")
    schemas = [name for name in vars(rigfile) if "BUDGET" in name]
    assert not schemas, f"expected no budget schema in rigfile.py, found {schemas}"
