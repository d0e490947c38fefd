"""The qtr part (RC-decay reflectance sensors) read in the loop as kit libraries read them
(host/tests/firmware/qtr_reads): each line driven high 10 us, made an input, and timed
until it reads 0, by a loop of value() reads and by machine.time_pulse_us; the times
follow the floor under each channel (the tape: black_us, the floor: white_us) and the
emitters (off: no light, the read times out); let go by an open drain's high too.

The line is one signal both ways (the part's ``io`` signal): the firmware's pin drives it
and lets it go when made an input, and the plant learns the instant from the CFG's own
time (docs/protocol.md), so the discharge starts there and both reads give the part's
white_us and black_us to the microsecond."""

import pytest

from host.tests.conftest import FIRMWARE, bench_app, results

pytestmark = pytest.mark.hil

RP2040 = ("rp2", "Raspberry Pi Pico with RP2040")
MOTORS = [
    {"kind": "dc_motor", "name": f"motor_{s}", "drives": side, "time_constant_ms": 0}
    for s, side in (("l", "left"), ("r", "right"))
]
QTR = {"kind": "qtr", "name": "line", "offsets_m": [[0.0, 0.0], [0.03, 0.0]], "white_us": 150, "black_us": 800}
TAPE = [[1.0, 0.2], [1.0, 1.8]]  # channel 0 over it, channel 1 3 cm ahead over the floor
PLANT = {"body": "differential", "start_pose": [1.0, 1.0, 0.0], "tape": TAPE, "parts": [*MOTORS, QTR]}
PINS = {"EMITTER": 26, "LINE0": 16, "LINE1": 17}
WIRING = {"EMITTER": "line.emitter", "LINE0": "line.0", "LINE1": "line.1"}


def test_discharge_times_follow_the_floor_and_the_emitters_by_value_loops_and_time_pulse_us(make_rig):
    app = bench_app("qtr_reads", PLANT, board="pins", identity=RP2040, wiring=WIRING, pins=PINS)
    rig = make_rig(app, main_dir=FIRMWARE / "qtr_reads", allow_exit=True)
    rig.run_for(0.2)
    truth = rig.truth()
    rig.stop()
    r = results(rig.console)
    assert "unlit_raw" in r, f"the firmware did not finish; console:\n{rig.console}"
    assert truth["line_on_tape"] == [True, False], truth
    assert r["pulse"] == [800, 150], f"time_pulse_us: the discharge time, to the microsecond: {r['pulse']}"
    assert r["loop"] == [800, 150], f"a loop of value() reads from the release to the fall: {r['loop']}"
    assert r["unlit_pulse"] == [2000, 2000] and r["unlit_raw"] == -1, "no light: the pulse outlasts the timeout"
    assert r["unlit_loop"] == [2000, 2000]
    assert r["drain_pulse"] == 800, "an open drain's high lets the line go as Pin.IN does (channel 0, the tape)"
    assert "[mpy-fil:" not in rig.console, rig.console
