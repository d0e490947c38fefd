"""The same pure modules on MicroPython's unix port give what CPython gives: the gain
schedule, NMEA parsing and a stretch of the mission (the board runs this code)."""

import json
import subprocess

from host.core import interpreter
from host.core.paths import REPO
from kalman import gain_schedule
from nmea import NmeaLines, dpt_depth_m

SCRIPT = """
import json
from kalman import gain_schedule
from nmea import NmeaLines, dpt_depth_m
from mission import Mission, FRONT
k_d, k_phi = gain_schedule()
lines = NmeaLines()
depths = [dpt_depth_m(s) for s in lines.feed(b"$SDDPT,7.5,0.0*55\\r\\n$SDDPT,1") + lines.feed(b"2.3,0.0*67\\r\\n")]
m = Mission(log=lambda *a: None)
for i in range(10):
    m.quantum(i * 500, 7.5, 0)
m.quantum(5000, None, FRONT)
for i in range(11, 60):
    m.quantum(i * 500, 7.2, 0)
print(json.dumps({"k_d": k_d, "k_phi": k_phi, "depths": depths, "d": m.filter.d_m, "stops": m.total_ms}))
"""


def run_micropython(script: str) -> dict:
    path = ":".join(str(REPO / "firmware" / p) for p in ("apps/pool_cleaner", "lib")) + ":.frozen"
    out = subprocess.run(
        [str(interpreter.find()), "-c", script], env={"MICROPYPATH": path}, capture_output=True, text=True, timeout=60
    )
    assert out.returncode == 0, f"MicroPython failed:\n{out.stdout}{out.stderr}"
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_pure_modules_give_the_same_results_on_micropython():
    mp = run_micropython(SCRIPT)
    k_d, k_phi = gain_schedule()
    assert max(abs(a - b) for a, b in zip(mp["k_d"] + mp["k_phi"], k_d + k_phi)) < 1e-9
    lines = NmeaLines()
    assert mp["depths"] == [dpt_depth_m(s) for s in lines.feed(b"$SDDPT,7.5,0.0*55\r\n$SDDPT,12.3,0.0*67\r\n")]
    assert 7.1 < mp["d"] < 7.4 and mp["stops"] != 0, mp
