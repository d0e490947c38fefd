"""Faults as data (sim_plant/faults.py, docs/campaigns.md): the schedule is checked with
messages naming the fault and the field, and each plant fault kind does to the signals
(or the robot) what its schedule says, from a stream of its own."""

import math

import pytest

from sim_plant.faults import FaultError, FaultyPlant, parse_faults, with_faults
from sim_plant.scripted import ScriptedPlant
from sim_plant.tests.rigs import duct_robot

S = 1_000_000


def sampled(period_us=100_000, until_s=10, value=1000):
    """An ADC that takes a sample every ``period_us``, of ``value`` + its sample number."""
    script = [(t, "adc", value + k) for k, t in enumerate(range(period_us, until_s * S + 1, period_us))]
    return ScriptedPlant(script, outputs={"adc": "u16", "pin": "level", "uart": "bytes"}, inputs={})


def square(period_us=1_000, until_s=10):
    """A level that flips every ``period_us`` (an encoder channel at constant speed)."""
    script = [(t, "pin", k % 2 == 0) for k, t in enumerate(range(period_us, until_s * S + 1, period_us))]
    script = [(t, n, int(v)) for t, n, v in script]
    return ScriptedPlant(script, outputs={"adc": "u16", "pin": "level"}, inputs={})


def faulty(plant, *faults, seed=1):
    wrapped = with_faults(plant, parse_faults(list(faults)))
    wrapped.reset(seed)
    return wrapped


def run(plant, until_s=10):
    return plant.advance_to(until_s * S)


def levels_alternate(changes) -> bool:
    values = [c.value for c in changes]
    return all(a != b for a, b in zip(values, values[1:]))


# -- the schedule ---------------------------------------------------------------------


@pytest.mark.parametrize(
    "entry, message",
    [
        ({"kind": "gremlin"}, "faults[0] kind: expected one of dropout"),
        ({"kind": "dropout", "start_s": 1}, "faults[0] (dropout): missing signal"),
        ({"kind": "stuck", "signal": "adc", "value": 70000}, "(stuck) value: expected 0 to 65535, got 70000"),
        ({"kind": "missed_edges", "signal": "pin", "rate": 1.5}, "(missed_edges) rate: expected 0 to 1, got 1.5"),
        ({"kind": "dropout", "signal": "adc", "start_s": 5, "end_s": 2}, "end_s: expected after start_s (5.0)"),
        ({"kind": "noise", "signal": "adc", "sd": "big"}, "(noise) sd: expected an integer or a number, got 'big'"),
        ({"kind": "bounce", "signal": "pin", "ms": 3}, "(bounce) ms: unknown field (fields of bounce: signal"),
        ({"kind": "wheel_slip", "wheel": "middle", "slip": 0.3}, "wheel: expected one of left, right, got 'middle'"),
        ({"kind": "heap", "size": "lots"}, "(heap) size: expected bytes like 64K"),
    ],
)
def test_a_bad_fault_is_refused_with_its_place_and_field(entry, message):
    with pytest.raises(FaultError) as e:
        parse_faults([entry])
    assert message in str(e.value), f"expected {message!r} in the error, got {e.value}"


def test_a_fault_on_a_signal_the_plant_lacks_or_of_the_wrong_kind_is_refused():
    with pytest.raises(FaultError, match=r"faults\[0\] \(dropout\) signal: the plant has no output 'sonar'"):
        faulty(sampled(), {"kind": "dropout", "signal": "sonar"})
    with pytest.raises(FaultError, match=r"adc is a u16 signal; bounce acts on level signals"):
        faulty(sampled(), {"kind": "bounce", "signal": "adc"})
    with pytest.raises(FaultError, match=r"needs a two-wheel robot plant, got ScriptedPlant"):
        faulty(sampled(), {"kind": "stuck_wheel", "wheel": "left"})


def test_harness_faults_leave_the_plants_signals_alone_and_are_kept_for_the_header():
    schedule = parse_faults([{"kind": "brownout", "at_s": 2}, {"kind": "heap", "size": "64K"}])
    assert with_faults(sampled(), ()) is not None and not isinstance(with_faults(sampled(), ()), FaultyPlant)
    plant = faulty(sampled(), *[{"kind": f.kind, **f.fields} for f in schedule])
    assert run(plant) == run(sampled()) and [f.kind for f in plant.schedule] == ["brownout", "heap"]


# -- signal faults ------------------------------------------------------------------------


def test_dropout_gives_no_adc_samples_inside_its_window_and_all_outside():
    plain = run(sampled())
    got = run(faulty(sampled(), {"kind": "dropout", "signal": "adc", "start_s": 2, "end_s": 4}))
    inside = [c for c in got if 2 * S <= c.t_us < 4 * S]
    assert not inside, f"expected no samples in 2-4 s, got {len(inside)}"
    assert [c for c in plain if not 2 * S <= c.t_us < 4 * S] == got, "expected every sample outside the window"


def test_dropout_holds_a_level_and_tells_the_true_level_when_it_ends():
    plant = faulty(square(period_us=300_000), {"kind": "dropout", "signal": "pin", "start_s": 1, "end_s": 2.05})
    got = run(plant, 3)
    assert not [c for c in got if 1 * S <= c.t_us < 2.05 * S], "expected the level held in the window"
    at_end = [c for c in got if c.t_us == round(2.05 * S)]
    true = square(period_us=300_000)
    true.advance_to(round(2.05 * S))
    held = [c for c in got if c.t_us < 1 * S][-1].value
    want = [] if held == true.output("pin") else [true.output("pin")]
    assert [c.value for c in at_end] == want, f"expected the true level told at 2.05 s, got {at_end}"
    assert levels_alternate(got), f"expected alternating levels, got {[c.value for c in got]}"


def test_stuck_adc_reads_its_value_only_inside_the_window():
    got = run(faulty(sampled(), {"kind": "stuck", "signal": "adc", "start_s": 3, "end_s": 5, "value": 7}))
    inside = {c.value for c in got if 3 * S <= c.t_us < 5 * S}
    outside = [c.value for c in got if not 3 * S <= c.t_us < 5 * S]
    assert inside == {7}, f"expected every sample in 3-5 s to read 7, got {inside}"
    assert 7 not in outside and len(got) == 100, f"expected 100 samples, the others true, got {len(got)}"


def test_stuck_level_is_forced_at_the_start_and_released_at_the_end():
    plant = faulty(
        square(period_us=250_000), {"kind": "stuck", "signal": "pin", "start_s": 1.1, "end_s": 2.1, "value": 1}
    )
    got = run(plant, 3)
    first = [c for c in got if c.t_us >= 1.1 * S][0]
    assert (first.t_us, first.value) == (round(1.1 * S), 1), f"expected 1 forced at 1.1 s, got {first}"
    assert all(c.value == 1 for c in got if 1.1 * S <= c.t_us < 2.1 * S)
    assert levels_alternate(got), f"expected alternating levels, got {[(c.t_us, c.value) for c in got]}"
    assert any(c.t_us >= 2.1 * S for c in got), "expected the level to move again after the window"


def test_wrong_values_are_scaled_and_offset_inside_the_window():
    got = run(
        faulty(sampled(), {"kind": "wrong", "signal": "adc", "start_s": 1, "end_s": 2, "scale": 0.5, "offset": 10})
    )
    plain = {c.t_us: c.value for c in run(sampled())}
    for c in got:
        want = round(plain[c.t_us] * 0.5 + 10) if 1 * S <= c.t_us < 2 * S else plain[c.t_us]
        assert c.value == want, f"at {c.t_us} us expected {want}, got {c.value}"


def test_a_noise_burst_has_the_scheduled_spread_and_nothing_outside():
    plant = faulty(
        sampled(period_us=1_000, until_s=10), {"kind": "noise", "signal": "adc", "start_s": 2, "end_s": 7, "sd": 50}
    )
    plain = {c.t_us: c.value for c in run(sampled(period_us=1_000, until_s=10))}
    got = run(plant)
    errors = [c.value - plain[c.t_us] for c in got if 2 * S <= c.t_us < 7 * S]
    sd = math.sqrt(sum(e * e for e in errors) / len(errors))
    assert 47 < sd < 53, f"expected a spread of about 50 counts over {len(errors)} samples, got {sd:.1f}"
    assert all(c.value == plain[c.t_us] for c in got if not 2 * S <= c.t_us < 7 * S)


def test_missed_edges_lose_whole_pulses_at_the_scheduled_rate():
    plain = run(square())
    got = run(faulty(square(), {"kind": "missed_edges", "signal": "pin", "rate": 0.1}))
    lost_pulses = (len(plain) - len(got)) / 2
    assert levels_alternate(got), "expected the levels to alternate (a lost pulse loses both its edges)"
    # every edge draws, but for the second edge of a lost pulse: N p / (1 + p) pulses lost
    want = len(plain) * 0.1 / 1.1
    assert 0.9 * want < lost_pulses < 1.1 * want, f"expected about {want:.0f} pulses lost, got {lost_pulses}"


def test_extra_edges_add_glitch_pulses_of_the_scheduled_width():
    fault = {"kind": "extra_edges", "signal": "pin", "rate": 0.2, "width_us": 20, "spread_us": 300}
    plain = run(square(until_s=2))
    got = run(faulty(square(until_s=2), fault), 2)
    extra = (len(got) - len(plain)) / 2
    assert 0.16 * len(plain) < extra < 0.24 * len(plain), (
        f"expected about 20 % of {len(plain)} edges glitched, got {extra}"
    )
    assert levels_alternate(got)
    real = {c.t_us for c in plain}
    glitch = [c for c in got if c.t_us not in real]
    widths = [b.t_us - a.t_us for a, b in zip(glitch[::2], glitch[1::2])]
    assert widths and all(w == 20 for w in widths), f"expected 20 us glitches, got {sorted(set(widths))}"


def test_bounce_follows_each_edge_within_its_window_and_settles_on_the_true_level():
    plain = run(square(period_us=100_000, until_s=2), 2)
    plant = faulty(
        square(period_us=100_000, until_s=2), {"kind": "bounce", "signal": "pin", "bounce_ms": 3, "pairs": 2}
    )
    got = run(plant, 2)
    assert levels_alternate(got)
    for edge in plain[:-1]:
        burst = [c for c in got if edge.t_us <= c.t_us < edge.t_us + 100_000]
        assert 3 <= len(burst) <= 5, f"expected the edge and 1-2 bounce pairs after {edge.t_us} us, got {burst}"
        assert burst[-1].t_us - edge.t_us <= 3_000 and burst[-1].value == edge.value


# -- the robot ------------------------------------------------------------------------


def duct(*faults, seed=3, **options):
    plant = duct_robot("bench_duct", **options)
    if faults:
        plant = with_faults(plant, parse_faults(list(faults)))
    plant.reset(seed)
    for name, value in (("motor_l.dir", 1), ("motor_r.dir", 1), ("motor_l.pwm", 30000), ("motor_r.pwm", 30000)):
        plant.set_input(name, value)
    return plant


def edges(changes, name):
    return sum(1 for c in changes if c.name == name)


def test_a_stuck_wheel_stops_its_encoder_and_turns_the_robot_inside_its_window():
    plant = duct({"kind": "stuck_wheel", "wheel": "left", "start_s": 1, "end_s": 2})
    before = plant.advance_to(1 * S)
    inside = plant.advance_to(2 * S)
    after = plant.advance_to(3 * S)
    assert edges(before, "enc_l.out") > 50 and edges(inside, "enc_l.out") <= 1, (
        "expected the left encoder still in 1-2 s"
    )
    assert edges(inside, "enc_r.out") > 50 and edges(after, "enc_l.out") > 50, (
        "expected the right wheel on, the left again after"
    )
    theta = plant.truth()["theta_rad"]
    assert theta > 0.3, f"expected the robot turned left about the jammed wheel, got {theta:.2f} rad"


def test_wheel_slip_keeps_the_encoder_counting_while_the_ground_moves_less():
    plain, slipping = duct(), duct({"kind": "wheel_slip", "wheel": "left", "start_s": 0.5, "end_s": 2.5, "slip": 0.5})
    a, b = plain.advance_to(3 * S), slipping.advance_to(3 * S)
    ratio = edges(b, "enc_l.out") / edges(a, "enc_l.out")
    assert 0.97 < ratio < 1.03, f"expected the slipping wheel's encoder to count as before, got {ratio:.2f} of it"
    theta = slipping.truth()["theta_rad"]
    assert theta > 0.5 and abs(plain.truth()["theta_rad"]) < 0.01, f"expected a turn to the left, got {theta:.2f} rad"


def spins(plant, n):
    """Spin on the spot ``n`` times, driving 0.5 s between."""
    for _ in range(n):
        plant.set_input("motor_l.dir", 0)
        plant.advance_to(plant.t_us + 300_000)
        plant.set_input("motor_l.dir", 1)
        plant.advance_to(plant.t_us + 500_000)


def test_tether_snags_come_at_their_rate_per_spin_from_their_own_stream():
    always = duct({"kind": "tether_snag", "rate": 1.0, "delay_ms": 100})
    spins(always, 5)
    assert always.truth()["fault_snags"] == 5 and always.truth()["fault_spins"] == 5
    half = [duct({"kind": "tether_snag", "rate": 0.5}, seed=s) for s in range(20)]
    for p in half:
        spins(p, 5)
    snags = sum(p.truth()["fault_snags"] for p in half)
    assert 30 <= snags <= 70, f"expected about 50 of 100 spins to snag, got {snags}"
    plain, snagging = duct(seed=4), duct({"kind": "tether_snag", "rate": 0.5}, seed=4)
    spins(plain, 5)
    spins(snagging, 5)
    assert plain.rng.random() == snagging.inner.rng.random(), "expected the plant's own stream untouched"


def test_the_same_seed_gives_the_same_faults_and_a_new_fault_leaves_the_others_draws_alone():
    noise = {"kind": "noise", "signal": "adc", "sd": 30}
    a = run(faulty(sampled(), noise, seed=5))
    b = run(faulty(sampled(), noise, seed=5))
    c = run(faulty(sampled(), noise, seed=6))
    assert a == b and a != c
    both = run(faulty(sampled(), noise, {"kind": "missed_edges", "signal": "pin", "rate": 0.5}, seed=5))
    assert [x for x in both if x.name == "adc"] == a, "expected the noise draws unchanged by a second fault"


def test_a_snapshot_and_restore_replays_the_same_faulty_stream():
    plant = faulty(
        square(), {"kind": "bounce", "signal": "pin"}, {"kind": "missed_edges", "signal": "pin", "rate": 0.3}
    )
    plant.advance_to(1 * S)
    snap = plant.snapshot()
    first = plant.advance_to(2 * S)
    plant.restore(snap)
    again = plant.advance_to(2 * S)
    assert first == again and first, "expected the same changes after a rewind"


def test_the_wrapper_stops_at_a_change_limit_and_keeps_the_plants_horizon():
    plant = faulty(square(), {"kind": "bounce", "signal": "pin", "bounce_ms": 0.3})
    got = plant.advance_to(5 * S, limit=4)
    assert 4 <= len(got) <= 4 + 7 and plant.t_us < 10_000, f"expected a stop near 4 changes, got {len(got)}"
    assert plant.next_change_us() > plant.t_us
    assert isinstance(plant, FaultyPlant) and plant.truth()["fault_events"]["bounce pin"] >= 1
