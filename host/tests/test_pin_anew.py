"""A pin made anew as it already is (docs/shim.md, "Pins"): no CFG and no sync for it, the
firmware reading the same levels (a driver that makes its pins at each read, as Kitronik's
ultrasonic does, paid three exchanges a read for nothing); a PWM's frequency set again as
it is: no OUT (Kitronik's motorOn sets it at each command)."""

import json

import pytest

pytestmark = pytest.mark.hil


def test_a_pin_made_as_it_is_sends_no_cfg(run_case):
    rig, r = run_case("pin_anew", 0.1, initial={"echo": 1}, trace=True)
    assert r == {"anew": (1, 0), "after": (1, 1)}, f"expected the levels read (1, 0) then (1, 1), got {r}"
    records = [json.loads(line) for line in (rig.artefacts / "trace.jsonl").read_text().splitlines()[1:]]
    cfgs = [(rec["pin"], rec["kind"], rec["pull"], rec["param"]) for rec in records if rec.get("msg") == "CFG"]
    # each pin's first CFG; the pull-up; the level 1; the PWM's; pin 25 the pin's again
    expected = [
        ("36", "pin", 0, -1),
        ("26", "pin", 0, 0),
        ("36", "pin", 1, -1),
        ("26", "pin", 0, 1),
        ("25", "pin", 0, 0),
        ("25", "pwm", 0, 5000),  # (its default frequency; the 1000 Hz follows as an OUT)
        ("25", "pin", 0, 0),
    ]
    assert cfgs == expected, f"expected the CFGs (pin, kind, pull, param) {expected}, got {cfgs}"
    pwm = next(rec["handle"] for rec in records if rec.get("msg") == "CFG" and rec["kind"] == "pwm")
    outs = [rec for rec in records if rec.get("msg") == "OUT" and rec["handle"] == pwm]
    freqs = [rec["value"] for rec in outs if rec["attr"] == "freq"]
    assert freqs == [1000, 2000], f"expected the PWM's frequency told at 1000 Hz then 2000 Hz, got {freqs}"
