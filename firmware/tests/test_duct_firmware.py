"""The duct robot's pure modules (seed 002) on CPython and on MicroPython's unix port: the
integer P law's truncation toward zero, the incremental speed loop, the sonar filter's
zero clamp and single-sample outlier rejection, the record ring's overruns and the link's
command parsing."""

import contextlib
import io
import json
import subprocess

from duct_link import RecordRing, format_batch, parse_command
from duct_sonar import ZERO_CLAMP, SonarFilter
from duct_speed import WheelLoop, p_step
from host.core import interpreter
from host.core.paths import REPO

SCRIPT = """
import json
from duct_speed import p_step, WheelLoop
from duct_sonar import SonarFilter
from duct_link import RecordRing
w = WheelLoop()
w.set(60)
duties = [w.update(c) for c in (0, 10, 40, 58, 61)]
f = SonarFilter()
vals = [f.push(v) for v in (70, 70, 200, 70, 20, 10)]
r = RecordRing(4)
for i in range(6):
    r.push(i, i, 0, 0, 0)
print(json.dumps({"p": [p_step(25, e) for e in (-7, -4, -3, 3, 4, 7, 60, -60)], "duties": duties,
                  "vals": vals, "drain": [x[0] for x in r.drain()], "over": r.overruns}))
"""


def expected():
    """What the same script prints on CPython."""
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        exec(SCRIPT, {})
    return json.loads(printed.getvalue())


def test_p_law_truncates_toward_zero_like_c():
    assert [p_step(25, e) for e in (-7, -4, -3, 3, 4, 7)] == [-1, -1, 0, 0, 1, 1]
    assert (-7 * 25) // 100 == -2  # Python's floor, which the firmware does not use


def test_speed_loop_is_incremental_and_clamped():
    w = WheelLoop()
    w.set(60)
    assert [w.update(c) for c in (0, 10, 40)] == [15, 20, 20]  # 0 + 15, +12 clamped at 20
    w.set(-30)  # a reversal starts from zero
    assert w.duty == 0 and w.update(0) == -7


def test_sonar_clamp_and_outlier():
    f = SonarFilter()
    assert [f.push(v) for v in (70, 70, 200, 70)] == [0, 70, 70, 70]  # 0 -> 70 waits a sample; 200 rejected
    assert f.rejected == 1
    assert [f.push(ZERO_CLAMP - 1), f.push(ZERO_CLAMP - 1)] == [70, 0]  # clamped to 0, once confirmed


def test_ring_overruns_and_commands():
    r = RecordRing(4)
    for i in range(6):
        r.push(i, i, 0, 0, 0)
    assert r.overruns == 2 and [x[0] for x in r.drain()] == [2, 3, 4, 5] and r.drain() == []
    assert parse_command("S 10 -10") == ("S", 10, -10) and parse_command("K 25") == ("K", 25)
    assert parse_command("E") == ("E",) and parse_command("S x 1") is None and parse_command("") is None
    assert format_batch([(1, 2, 3, 4, 5, 6)], 0) == "D 1 2 3 4 5 6\nK 0\n"


def test_same_on_micropython():
    path = str(REPO / "firmware" / "apps" / "duct" / "lib")
    out = subprocess.run(
        [str(interpreter.find()), "-c", SCRIPT], env={"MICROPYPATH": path}, capture_output=True, text=True, timeout=60
    )
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout) == expected()
