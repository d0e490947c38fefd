"""Wall-clock figures of the core loop: ``python -m host.bench`` (``make bench``).

- lockstep real-time factor: simulated seconds per wall second for 10 simulated minutes
  of the rover firmware at 50 ms control quanta;
- link round trip: host sends STATE -> shim answers WAIT, p50/p99 in microseconds,
  measured with a firmware that does nothing but toggle a pin and sleep;
- pool cleaner mission: the whole 25 x 8 m pool (about an hour simulated) from start to
  "done", its real-time factor (target >= 60x: the hour in a minute).
These are measurements, not pass/fail tests; the target figures are printed beside them.
"""

import argparse
import math
import os
import statistics
import time
from pathlib import Path

from host.rig import Rig

PING = Path(__file__).parent / "tests" / "firmware" / "ping"


def percentile(values, pct):
    values = sorted(values)
    return values[min(len(values) - 1, int(pct / 100 * len(values)))]


def bench_rover(sim_s: float) -> dict:
    with Rig("rover", seed=1, time_round_trips=True) as rig:
        t0 = time.perf_counter()
        step = 60.0
        done = 0.0
        while done < sim_s:
            rig.run_for(min(step, sim_s - done))
            done = rig.t_us / 1e6
            print(f"  rover: {done:6.0f} / {sim_s:.0f} simulated s", end="\r", flush=True)
        wall = time.perf_counter() - t0
        print()
        return {
            "sim_s": sim_s,
            "wall_s": wall,
            "rtf": sim_s / wall,
            "round_trips": rig.stats.link_round_trips,
            "wake_rtt": rig.stats.round_trip_us,
            "control": rig.budgets["control.period"].stats(),
        }


def bench_pool(limit_s: float = 75 * 60) -> dict:
    with Rig("pool_cleaner", seed=1) as rig:
        t0 = time.perf_counter()
        while "done:" not in rig.console and rig.t_us < limit_s * 1e6:
            rig.run_for(60.0)
            print(f"  pool cleaner: {rig.t_us / 60e6:4.0f} simulated min", end="\r", flush=True)
        wall = time.perf_counter() - t0
        print()
        sim_s = rig.t_us / 1e6
        return {
            "sim_s": sim_s,
            "wall_s": wall,
            "rtf": sim_s / wall,
            "done": "done:" in rig.console,
            "round_trips": rig.stats.link_round_trips,
            "coverage": rig.truth()["coverage_fraction"],
        }


def bench_ping(sim_s: float) -> list[float]:
    with Rig("rover", seed=0, main_dir=PING, time_round_trips=True) as rig:
        rig.run_for(sim_s)
        return rig.stats.round_trip_us[10:]


def bench_campaign(workers: int, runs: int = 8, sim_s: float = 120.0, busy_poll: bool = True) -> dict:
    """A campaign of ``runs`` rover runs of ``sim_s`` simulated seconds on ``workers`` local
    processes: its wall time from the pool's start to the last result (docs/campaigns.md).
    ``busy_poll`` False: a lone worker does not busy-poll its spare core either."""
    import tempfile

    from host.campaign import load_campaign
    from host.campaign.runner import run_campaign

    campaign = load_campaign("rover", seeds=runs, seconds=sim_s, step_s=10.0)
    before = os.environ.get("MPY_FIL_BUSY_POLL")
    if not busy_poll:
        os.environ["MPY_FIL_BUSY_POLL"] = "0"  # (the pool's processes inherit it)
    try:
        with tempfile.TemporaryDirectory(prefix="mpy-fil-bench-") as out:
            t0 = time.perf_counter()
            results = run_campaign(campaign, out, workers=workers)
            wall = time.perf_counter() - t0
    finally:
        if before is None:
            os.environ.pop("MPY_FIL_BUSY_POLL", None)
        else:
            os.environ["MPY_FIL_BUSY_POLL"] = before
    return {
        "runs": len(results),
        "passed": sum(r["passed"] for r in results),
        "wall_s": wall,
        "per_min": len(results) / wall * 60,
        "cpu_s": statistics.median(r.get("cpu_s", math.nan) for r in results),
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m host.bench", description=__doc__.split("\n")[0])
    parser.add_argument("--sim-minutes", type=float, default=10.0, help="simulated minutes of the rover (default 10)")
    parser.add_argument("--no-pool", action="store_true", help="skip the pool cleaner's full mission")
    args = parser.parse_args(argv)
    print(f"core loop benchmark: rover firmware, {args.sim_minutes:g} simulated minutes, 50 ms control quanta")
    rover = bench_rover(args.sim_minutes * 60)
    print(
        f"  lockstep real-time factor: {rover['rtf']:.0f}x  ({rover['sim_s']:.0f} simulated s in "
        f"{rover['wall_s']:.2f} wall s; target >= 100x)"
    )
    print(
        f"  link exchanges: {rover['round_trips']} ({rover['round_trips'] / rover['sim_s']:.0f} per simulated s); "
        f"control steps {rover['control']['count']}, misses {rover['control']['misses']}"
    )
    wake = rover["wake_rtt"]
    print(
        f"  per-wake round trip incl. firmware work: p50 {percentile(wake, 50):.0f} us, "
        f"p99 {percentile(wake, 99):.0f} us"
    )
    ping = bench_ping(2.0)
    print(
        f"  link round trip (STATE -> WAIT, {len(ping)} exchanges): p50 {percentile(ping, 50):.0f} us, "
        f"p99 {percentile(ping, 99):.0f} us, mean {statistics.fmean(ping):.0f} us"
    )
    one, lone, two = bench_campaign(1), bench_campaign(1, busy_poll=False), bench_campaign(2)
    print(
        f"campaign throughput ({one['runs']} rover runs of 120 simulated s; load average {os.getloadavg()[0]:.1f} "
        f"on {os.cpu_count()} cores): 1 worker {one['per_min']:.1f} runs/min ({lone['per_min']:.1f} without "
        f"busy polling), 2 workers {two['per_min']:.1f} runs/min: {two['per_min'] / one['per_min']:.2f}x "
        f"({two['per_min'] / lone['per_min']:.2f}x; target >= 1.7x); CPU per run {one['cpu_s']:.2f} s, "
        f"{lone['cpu_s']:.2f} s, {two['cpu_s']:.2f} s"
    )
    if not args.no_pool:
        print("pool cleaner, full mission: 25 x 8 m pool, NMEA sonar byte by byte, 50 ms control quanta")
        pool = bench_pool()
        print(
            f"  full mission real-time factor: {pool['rtf']:.0f}x  ({pool['sim_s'] / 60:.1f} simulated min in "
            f"{pool['wall_s']:.1f} wall s; target >= 60x){'' if pool['done'] else ' -- NOT DONE'}"
        )
        print(
            f"  link exchanges: {pool['round_trips']} ({pool['round_trips'] / pool['sim_s']:.0f} per simulated s); "
            f"floor covered {pool['coverage']:.1%}"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
