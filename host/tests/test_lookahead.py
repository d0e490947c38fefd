"""The host's lookahead (docs/clock.md): a STATE carries the inputs past the wait's end,
the shim applies each at its time, and an output inside voids the rest. The firmware must
see exactly what it sees without it: the same outputs at the same times, the same ground
truth, the same console, with fewer exchanges where the firmware often wakes to find
nothing to drive."""

import hashlib

import pytest

from host.rig import Recording, Rig, RigSpec


def run(tmp_path, app: str, seconds: float, lookahead: bool) -> tuple[dict, int, int]:
    folder = tmp_path / f"{app}-{'look' if lookahead else 'plain'}"
    rig = Rig(RigSpec(app, seed=3), Recording(record=True, artefacts=folder))
    if not lookahead:
        rig.clock.lookahead_us = 0
    with rig:
        rig.run_for(seconds)
        exchanges, rollbacks = rig.stats.link_round_trips, rig.stats.rollbacks
    digests = {f: hashlib.sha256((folder / f).read_bytes()).hexdigest() for f in ("signals.csv", "truth.csv")}
    digests["console"] = hashlib.sha256(rig.console.encode()).hexdigest()
    return digests, exchanges, rollbacks


@pytest.mark.parametrize(
    ("app", "seconds", "fewer"),
    [
        ("duct", 8.0, 2.5),  # a 160 Hz timer, slot encoders, a record stream: most wakes drive nothing
        ("lab_robot", 3.0, 0.9),  # reads its program jumper at boot, after the first lookahead
        ("rover", 5.0, 0.9),  # drives its probe pin at every wake: every lookahead is voided
    ],
)
def test_the_firmware_sees_the_same_with_and_without_the_lookahead(tmp_path, app, seconds, fewer):
    plain, plain_exchanges, _ = run(tmp_path, app, seconds, lookahead=False)
    looked, look_exchanges, rollbacks = run(tmp_path, app, seconds, lookahead=True)
    assert looked == plain, f"expected the same outputs, truth and console with the lookahead; artefacts in {tmp_path}"
    assert plain_exchanges / look_exchanges >= fewer, (
        f"expected {fewer}x fewer exchanges with the lookahead, got {plain_exchanges} without and "
        f"{look_exchanges} with ({rollbacks} rewinds)"
    )
