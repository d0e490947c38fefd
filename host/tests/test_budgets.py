"""Timing budgets that the pool cleaner added: sentence periods on a UART (counted at a
marker byte) and track-stop pulses (one of two outputs at 1)."""

import pytest

from host.rig.budgets import COMPUTE, LEVEL, Budget, BudgetHooks, PeriodBudget, PulseBudget


def test_a_uart_period_counts_chunks_with_the_marker_byte_only():
    budget = PeriodBudget("sonar.period", "sonar.uart", period_us=500_000, tolerance_us=1_000, marker=b"$")
    events = [(102_083, b"$"), (104_166, b"S"), (139_583, b"\r\n"), (602_083, b"$SDD"), (1_102_083, b"$")]
    for t, chunk in events:
        if budget.counts(chunk):
            budget.event(t)
    assert budget.values == [500_000, 500_000] and budget.misses == 0
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
    assert budget.values == [250_000, 350_000, 100_000] and budget.misses == 1


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
    assert period.values == [500_000]


def test_a_hook_on_an_unknown_event_is_refused_by_name():
    class Odd(Budget):
        def hooks(self):
            return [("tick", "x", print)]

    with pytest.raises(ValueError, match="budget odd: unknown event 'tick'"):
        BudgetHooks([Odd("odd", "x", limit_us=1)])
