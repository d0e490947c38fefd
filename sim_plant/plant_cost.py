"""Plant cost per 50 ms control quantum, for each robot: ``python -m sim_plant.plant_cost``.

Each robot cruises in its world as its firmware would drive it (both wheels at a
cruising duty, a steering correction every second, the HC-SR04 pinged every 150 ms) for
``QUANTA`` quanta. Two figures per robot:

* **host loop**: the way the host's rig drives a plant, event by event
  (``next_change_us`` then ``advance_to`` up to each change), which is the real cost;
* **one call**: one ``advance_to`` per quantum (a lower bound: the same events, fewer calls);

and the cost of a ``snapshot()`` plus a ``restore()`` (the host's rollback of a
speculative batch of IRQ edges).

Wall-clock time is measured here, in the benchmark, never in the plant.
"""

import time
from pathlib import Path

from sim_plant.catalogue.assembly import assemble_file
from sim_plant.world import box, duct_network, room

QUANTUM_US = 50_000
QUANTA = 600  # 30 s of virtual time per robot
TARGET_US = 50.0
APPS = Path(__file__).resolve().parents[1] / "firmware" / "apps"
POOL_RIG = APPS / "pool_cleaner" / "rig.toml"
DUCT_RIG = APPS / "duct" / "rig.toml"
DUCT_CRAWL = {"v_max_m_s": 0.4, "motor_l.deadband_duty": 0.1, "motor_r.deadband_duty": 0.1}
"""The duct robot as the benchmark has always driven it: its weave at 0.4 m/s full duty."""


def _forward_weaving(p, k: int, duty: int) -> None:
    """Both TB6612 channels forward at ``duty``, weaving (see :func:`_weave`)."""
    if k == 0:
        for side in "lr":
            p.set_input(f"motor_{side}.in1", 1)
            p.set_input(f"motor_{side}.pwm", duty)
    _weave(p, "motor_l.pwm", "motor_r.pwm", duty, 2_000, k)


def _rover(p, k):
    _forward_weaving(p, k, 30_000)


def _weave(p, left: str, right: str, duty: int, delta: int, k: int) -> None:
    """A steering correction each second, alternately left and right (stays on course)."""
    phase = k % 40
    p.set_input(left, duty + (delta if 10 <= phase < 20 else 0))
    p.set_input(right, duty + (delta if 30 <= phase < 40 else 0))


def _pool(p, k):
    p.set_input("track_l.stop" if k % 40 < 20 else "track_r.stop", 1 if k % 20 == 0 else 0)


def _duct(p, k):
    if k == 0:
        p.set_input("motor_l.dir", 1)
        p.set_input("motor_r.dir", 1)
    _weave(p, "motor_l.pwm", "motor_r.pwm", 30_000, 1_000, k)


def _vacuum(p, k):
    _forward_weaving(p, k, 40_000)
    if k % 3 == 0:  # one servo step and one ping per 150 ms sensing task (seed 003 §4.1)
        p.set_input("servo.pwm", (1638, 3276, 4915, 6553, 8191)[(k // 3) % 5])
        p.set_input("sonar.trig", 1)
        p.advance_to(p.t_us + 10)
        p.set_input("sonar.trig", 0)


def _lab(p, k):
    _weave(p, "motor_l.in1", "motor_r.in1", 40_000, 2_000, k)


# worlds long enough for 30 s of cruising: the figures are for a robot under way
LONG_DUCT = duct_network([(0.0, 0.0, 20.0, 0.4), (6.0, -1.0, 6.4, 0.0), (9.0, 0.4, 9.4, 1.4)], name="bench duct")
LONG_ROOM = room(40.0, 4.0, [box(12.0, 2.5, 0.4, 0.4), box(20.0, 3.0, 0.6, 0.3)], name="bench room")


ROBOTS = [
    ("rover (rig file)", lambda: assemble_file(APPS / "rover" / "rig.toml", room_w_m=40.0), _rover),
    (
        "pool cleaner (tracked, NMEA)",
        lambda: assemble_file(POOL_RIG, pool_length_m=200.0, start_pose=(0.46, 0.5, 0.0)),
        _pool,
    ),
    (
        "duct robot (differential, duct parts)",
        lambda: in_world(assemble_file(DUCT_RIG, **DUCT_CRAWL), LONG_DUCT),
        _duct,
    ),
    (
        "vacuum robot (rig file)",
        lambda: in_world(assemble_file(APPS / "vacuum" / "rig.toml"), LONG_ROOM, (0.5, 0.5, 0.0)),
        _vacuum,
    ),
    (
        "lab robot (rig file)",
        lambda: assemble_file(APPS / "lab_robot" / "rig.toml", room_w_m=40.0, start_pose=[1.0, 2.0, 0.0]),
        _lab,
    ),
]


def in_world(plant, world, start_pose=None):
    """``plant`` rebuilt in ``world`` (a World of the benchmark's own), at ``start_pose``
    or where its rig file starts it."""
    pose = start_pose or plant.start_pose
    plant.body.world_and_pose = lambda *rng: (world, pose)  # (a body that draws its world takes the generator)
    plant.reset(0)
    return plant


def run(make, drive, *, host_loop: bool, quanta: int = QUANTA) -> tuple[float, float]:
    """(us of wall time per quantum, output changes per quantum)."""
    plant = make()
    plant.reset(1)  # building the plant is not part of the figure
    changes = 0
    t0 = time.perf_counter()
    for k in range(quanta):
        drive(plant, k)
        end = (k + 1) * QUANTUM_US
        if host_loop:
            while plant.t_us < end:
                changes += len(plant.advance_to(min(plant.next_change_us(), end)))
        else:
            changes += len(plant.advance_to(end))
    elapsed = time.perf_counter() - t0
    return elapsed / quanta * 1e6, changes / quanta


def snapshot_cost(make, drive, repeats: int = 200) -> float:
    """us for one snapshot() and one restore() of a plant under way."""
    plant = make()
    plant.reset(1)
    for k in range(40):
        drive(plant, k)
        plant.advance_to((k + 1) * QUANTUM_US)
    t0 = time.perf_counter()
    for _ in range(repeats):
        plant.restore(plant.snapshot())
    return (time.perf_counter() - t0) / repeats * 1e6


def main() -> None:
    print(f"plant cost per {QUANTUM_US // 1000} ms quantum ({QUANTA} quanta each; target <= {TARGET_US:.0f} us)")
    print(f"{'robot':36} {'host loop us':>13} {'one call us':>12} {'changes/q':>10} {'snap+restore us':>16}")
    for name, make, drive in ROBOTS:
        host_us, per_q = min((run(make, drive, host_loop=True) for _ in range(3)), key=lambda r: r[0])
        call_us, _ = min((run(make, drive, host_loop=False) for _ in range(3)), key=lambda r: r[0])
        snap_us = min(snapshot_cost(make, drive) for _ in range(3))
        flag = "" if host_us <= TARGET_US else "  (over target)"
        print(f"{name:36} {host_us:13.1f} {call_us:12.1f} {per_q:10.1f} {snap_us:16.1f}{flag}")


if __name__ == "__main__":
    main()
