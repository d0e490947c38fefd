"""Wall-clock figures of the core loop: ``python -m host.bench`` (``make bench``).

- lockstep real-time factor: simulated seconds per wall second for 10 simulated minutes
  of the rover firmware at 50 ms control quanta;
- link round trip: host sends STATE -> shim answers WAIT, p50/p99 in microseconds,
  measured with a firmware that does nothing but toggle a pin and sleep.
These are measurements, not pass/fail tests; the target figures are printed beside them.
"""

import argparse
import statistics
import time
from pathlib import Path

from host.runner import Rig

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


def bench_ping(sim_s: float) -> list[float]:
    with Rig("rover", seed=0, main_dir=PING, time_round_trips=True) as rig:
        rig.run_for(sim_s)
        return rig.stats.round_trip_us[10:]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m host.bench", description=__doc__.split("\n")[0])
    parser.add_argument("--sim-minutes", type=float, default=10.0, help="simulated minutes of the rover (default 10)")
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
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
