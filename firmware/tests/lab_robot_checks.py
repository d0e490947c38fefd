# The lab robot's pure modules run on the seed's cases. test_lab_robot_algorithms.py runs
# this under CPython and on MicroPython's unix port and compares what it returns with the
# seed's numbers. MicroPython code: no f-strings, no typing.
import math

from dead_reckoning import MM_PER_COUNT, TRACK_MM, Odometry
from goto import ACHIEVED, DRIVE, ROTATE, GoTo, profile_mm_s
from quadrature import Quadrature
from square import waypoints
from wall_follow import nearest_wall, rotation_deg_s

FORWARD = ((1, 0), (1, 1), (0, 1), (0, 0))  # Table 1 from phase 0: 1, 2, 3, 0
DT_MS = 50


def decode(levels, start=(0, 0)):
    q = Quadrature(*start)
    for a, b in levels:
        q.edge(a, b)
    return q


def steps(n, sequence=FORWARD):
    return [sequence[i % 4] for i in range(n)]


def decoding():
    out = {}
    for n in (1, 3, 4, 7, 80, 1001):
        q = decode(steps(n))
        out["forward_%d" % n] = [q.count, q.errors, q.count * MM_PER_COUNT]
        back = decode(steps(n, ((0, 1), (1, 1), (1, 0), (0, 0))))
        out["backward_%d" % n] = [back.count, back.errors]
    # 5 steps forward, then a jump from phase 1 to phase 3 (two edges in one handler)
    q = decode(steps(5) + [(0, 1)])
    out["jump"] = [q.count, q.errors]
    q = decode(steps(2) + [(1, 1)])  # the same phase again: a handler with nothing new
    out["repeat"] = [q.count, q.errors, q.idle]
    return out


def odometry():
    out = {}
    odo = Odometry(theta_rad=0.3)
    for _ in range(100):
        odo.update(2.5, 2.5, DT_MS)
    out["straight"] = [odo.theta_rad, odo.x_mm, odo.y_mm, odo.v_mm_s, odo.w_rad_s]
    quarter = TRACK_MM * math.pi / 2  # S_R - S_L = w pi / 2
    odo = Odometry()
    odo.update(-quarter / 2, quarter / 2, DT_MS)
    out["turn_one_step"] = [odo.theta_rad, odo.x_mm, odo.y_mm]
    odo = Odometry()
    for _ in range(40):
        odo.update(100.0 / 40, (100.0 + quarter) / 40, DT_MS)
    out["turn_driving"] = [odo.theta_rad, odo.s_l_mm, odo.s_r_mm]
    odo = Odometry()
    odo.update(30.0, 50.0, DT_MS)  # Eq. 5 with S(-dt) = 0: the first step's speed
    out["first_speed"] = [odo.v_mm_s, odo.w_rad_s]
    return out


def run_goto(goal, close_mm=10.0, limit=400):
    """GoTo driving an ideal robot (its commands hold for one step, odometry exact)."""
    goto = GoTo(close_mm=close_mm)
    goto.set_goal(*goal)
    odo = Odometry()
    log = []
    for _ in range(limit):
        v, w = goto.step(odo)
        log.append((goto.state, v, w))
        if goto.state == ACHIEVED:
            break
        dth = w * DT_MS / 1000
        ds = v * DT_MS / 1000
        half = dth * TRACK_MM / 2
        odo.update(ds - half, ds + half, DT_MS)
    rotating_v = max([abs(v) for state, v, w in log if state == ROTATE] or [0.0])
    driving_w = max([abs(w) for state, v, w in log if state == DRIVE] or [0.0])
    return {
        "achieved": goto.state == ACHIEVED,
        "steps": len(log),
        "dist_mm": goto.dist_mm,
        "theta_deg": math.degrees(odo.theta_rad),
        "max_v_while_rotating": rotating_v,
        "max_v": max(v for state, v, w in log),
        "max_w_while_driving": driving_w,
    }


def goto():
    out = {"profile": [profile_mm_s(2000.0), profile_mm_s(100.0), profile_mm_s(10.0)]}
    out["ahead"] = run_goto((2000.0, 0.0))
    out["left"] = run_goto((0.0, 2000.0))
    try:
        GoTo(close_mm=0)
        out["close_zero"] = "accepted"
    except ValueError as e:
        out["close_zero"] = str(e)
    out["waypoints"] = [list(p) for p in waypoints()]
    return out


def wall():
    out = {}
    r = 140.0
    d = 400.0  # a wall parallel to the robot, 400 mm to its left
    s = math.sqrt(0.5)
    out["parallel"] = list(nearest_wall(d - r, (d - r * s) / s))
    # the same wall turned 10 degrees towards the robot's left-front (ahead it is farther)
    a = math.radians(10)
    n = (-math.sin(a), math.cos(a))  # the wall's normal; points p with n . p = d

    def hit(mx, my, axis):
        ux, uy = math.cos(axis), math.sin(axis)
        return (d - (n[0] * mx + n[1] * my)) / (n[0] * ux + n[1] * uy)

    out["turned"] = list(nearest_wall(hit(0.0, r, math.pi / 2), hit(r * s, r * s, math.pi / 4)))
    out["rotation"] = [rotation_deg_s(b) for b in (100.0, 90.5, 88.0, 80.0, -80.0, -100.0)]
    return out


def results():
    return {"decoding": decoding(), "odometry": odometry(), "goto": goto(), "wall": wall()}
