"""The recorder keeps what the firmware really saw, also through speculative batches that
a handler's output write rolls back."""

import pytest

pytestmark = pytest.mark.hil


def test_a_rolled_back_batch_leaves_each_input_change_recorded_once_at_its_time(run_case):
    script = [(1000, "a", 1), (1500, "b", 1), (2000, "a", 0), (2500, "b", 0), (3000, "a", 1), (7000, "b", 1)]
    rig, r = run_case("irq_writes", 0.02, script, record=True)
    assert rig.stats.rollbacks >= 1, "the scenario must exercise a rollback"
    rec = rig.recorder
    sensed = [e for e in rec.events if rec.signals[e[1]]["role"] == "sensor"]
    assert sensed == script, f"expected the script once, in order; recorded {sensed}"
    out1 = [(t, v) for t, name, v in rec.events if name == "out1"]
    assert out1 == [(0, 0), (1000, 1), (2000, 0), (3000, 1)], out1
    assert rig.plant.log == [(t, "out1", v) for t, v in out1], "the recording and the plant disagree"
    times = [t for t, _row in rec.truth]
    assert times == sorted(set(times)) and times[0] == 0, times
    assert all(b - a <= rec.truth_period_us + 20_000 for a, b in zip(times, times[1:])), times


def test_the_probe_and_an_unwired_output_are_recorded_under_their_own_names(run_case):
    rig, _ = run_case("unwired", 0.1, record=True)
    signals = rig.recorder.signals
    assert signals["probe:control"]["role"] == "probe" and signals["pin.2"]["role"] == "pin", signals
    led = [(t, v) for t, name, v in rig.recorder.events if name == "pin.2"]
    probe = [(t, v) for t, name, v in rig.recorder.events if name == "probe:control"]
    assert led == [(0, 0), (10_000, 1), (20_000, 0), (30_000, 1), (40_000, 0)], led
    assert probe == [(0, 0), (0, 1), (10_000, 0), (20_000, 1), (30_000, 0), (40_000, 1)], probe
