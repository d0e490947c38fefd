"""The same pure modules on MicroPython's unix port give what CPython gives: the pool
cleaner's gain schedule, NMEA parsing and a stretch of its mission; the vacuum robot's
unicycle conversion, ensure_W, map(), odometry (with and without the listed mean-filter
bug), heading controller and avoidance heading (the board runs this code)."""

import json
import math
import subprocess

from avoidance import Obstacles
from go_to_goal import GAIN_SETS, HeadingController
from host.core import interpreter
from host.core.paths import REPO
from kalman import gain_schedule
from nmea import NmeaLines, dpt_depth_m
from odometry import Odometry
from unicycle import arduino_map

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


def run_micropython(script: str, folders=("apps/pool_cleaner", "lib")) -> dict:
    path = ":".join(str(REPO / "firmware" / p) for p in folders) + ":.frozen"
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


VACUUM_SCRIPT = """
import json, math
from unicycle import uni_to_diff, ensure_w, icc_radius, arduino_map
from odometry import Odometry
from go_to_goal import HeadingController, GAIN_SETS, wheel_pwm
from avoidance import Obstacles
from scheduler import QuantumScheduler

def ratio(bug):
    odo = Odometry(wheel_diameter_cm=6.5, slots=20, track_cm=18.0, window=5, mean_bug=bug)
    for k in range(1, 401):
        x = odo.update(3 * k, 3 * k)[0]
        if k == 200:
            half = x
    return (x - half) / (200 * 3 * math.pi * 6.5 / 20)

odo = Odometry(wheel_diameter_cm=6.5, slots=20, track_cm=18.0)
poses = [odo.update(k, 2 * k) for k in range(40)]
ctl = HeadingController(*GAIN_SETS[2])
pwms = [ctl.step(0.3 * math.sin(k / 3), 0.0, 15.0) for k in range(20)]
obs = Obstacles()
for i, d in enumerate((35.0, 40.0, 60.0, None, None)):
    obs.add(i, d, (10.0, 5.0, 0.2))
sched = QuantumScheduler(((0, 2), (1, 10), (2, 3)))
print(json.dumps({
    "diff": uni_to_diff(10.0, 1.0, 20.0), "ensure": ensure_w(15.0, 2.0, 20.0, 30.0, 30.0, 3.0),
    "icc": icc_radius(0.0, 12.0, 20.0), "map": [arduino_map(v, 8, 30, 107, 228) for v in (-10.0, 15.9, 45.0)],
    "pwm": [wheel_pwm(v) for v in (-12.0, 0.0, 60.0)], "bias": [ratio(True), ratio(False)],
    "poses": poses[-1], "pwms": pwms, "ao": obs.heading((10.0, 5.0, 0.2), (300.0, 0.0)),
    "sched": [list(sched.due()) for _ in range(30)],
}))
"""


def test_the_vacuum_robots_pure_modules_give_the_same_results_on_micropython():
    """Seed 003 notes §9 on the board's interpreter: V 10, W 1, L 20 gives (0, 20);
    ensure_W (-10, 30); R = L/2; the listed mean filter x1.25, as meant x1.000; and the
    same odometry, PWM commands and avoidance heading as CPython computes."""
    mp = run_micropython(VACUUM_SCRIPT, ("apps/vacuum/lib", "lib"))
    assert mp["diff"] == [0.0, 20.0] and mp["ensure"] == [-10.0, 30.0] and mp["icc"] == 10.0
    assert mp["map"] == [arduino_map(v, 8, 30, 107, 228) for v in (-10.0, 15.9, 45.0)] == [8, 145, 310]
    assert mp["pwm"] == [0, 63, 255]
    assert abs(mp["bias"][0] - 1.25) < 1e-3 and abs(mp["bias"][1] - 1.0) < 1e-9
    odo = Odometry(wheel_diameter_cm=6.5, slots=20, track_cm=18.0)
    pose = [odo.update(k, 2 * k) for k in range(40)][-1]
    assert max(abs(a - b) for a, b in zip(mp["poses"], pose)) < 1e-9
    ctl = HeadingController(*GAIN_SETS[2])
    assert mp["pwms"] == [list(ctl.step(0.3 * math.sin(k / 3), 0.0, 15.0)) for k in range(20)]
    obs = Obstacles()
    for i, d in enumerate((35.0, 40.0, 60.0, None, None)):
        obs.add(i, d, (10.0, 5.0, 0.2))
    assert abs(mp["ao"] - obs.heading((10.0, 5.0, 0.2), (300.0, 0.0))) < 1e-9
    assert [len(d) for d in mp["sched"]].count(3) == 1 and sum(0 in d for d in mp["sched"]) == 15
