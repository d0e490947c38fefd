"""How much of the host's work an exchange is the plant's own: a lockstep robot run with
every call the rig makes on its plant recorded, then those calls replayed on a fresh plant
(the same spec and seed), each result compared with the run's, and the replay's CPU time
and the run's host CPU time printed an exchange, beside what a share of the exchange's
floor (the raw round trip and the interpreter's CPU, as ``make bench`` counts it) leaves
the host (docs/bench.md, "What the floors leave the host").

    PYTHONPATH=. python host/bench/plant_share.py rover 60 [--repeat 5] [--share 0.65]
    PYTHONPATH=. python host/bench/plant_share.py pool_cleaner 60

The host's CPU time comes from runs of their own (the recording's wrapper costs), which
poll the link by blocking (busy polling off): its own work, not its wait for the
firmware; the recorded run must make the same exchanges. Each time printed is the least of
``--repeat`` (the machine's load only adds to a CPU time). A replay whose results differ
from the run's stops with the call that differed: the plant was changed outside its calls
(a bus chip written through a device the rig holds, say), and its share would not be the
plant's. Only the plant's own methods and attributes are recorded, so a robot whose rig
reaches into the plant's parts (bus chips, PIO) is refused that way rather than
under-counted.
"""

import argparse
import resource
import sys
import time
from operator import methodcaller

import host.bench as bench
from host.rig import Recording, Rig, RigSpec
from host.rig.loop.spec import build_plant


class RecordedPlant:
    """The plant as the rig sees it, every method call and attribute write kept in order:
    (name, args, result), a snapshot's result by its index, a list argument (an out
    parameter such as ``advance_edges``' segments) as a fresh empty list on replay."""

    def __init__(self, plant):
        object.__setattr__(self, "_target", plant)  # (the calls forwarded by name: what the rig asked, no probing)
        object.__setattr__(self, "calls", [])
        object.__setattr__(self, "_snaps", {})
        object.__setattr__(self, "_made", [0])  # snapshots so far (an id may come again once one is dropped)

    def __getattr__(self, name):
        value = getattr(self._target, name)
        if not callable(value) or name.startswith("__"):
            return value
        calls, snaps = self.calls, self._snaps

        def call(*args):
            kept = tuple(
                ("snap", snaps[id(a)]) if id(a) in snaps else ("list",) if type(a) is list else a for a in args
            )
            result = value(*args)
            if name == "snapshot":
                snaps[id(result)] = self._made[0]
                self._made[0] += 1
                kept_result = ("snap", snaps[id(result)])
            elif type(result) is list:
                kept_result = list(result)
            else:
                kept_result = result
            calls.append((name, kept, kept_result))
            return result

        return call

    def __setattr__(self, name, value):
        self.calls.append(("__setattr__", (name, value), None))
        setattr(self._target, name, value)


def replay(plant, calls: list, check: bool, snaps: list) -> float:
    """The calls on ``plant`` (fresh, as the run's was built; ``snaps`` its snapshots so far);
    the process's CPU seconds."""
    t0 = time.process_time()
    for i, (name, kept, expected) in enumerate(calls):
        if name == "__setattr__":
            setattr(plant, *kept)
            continue
        args = [snaps[a[1]] if type(a) is tuple and a[:1] == ("snap",) else [] if a == ("list",) else a for a in kept]
        result = methodcaller(name, *args)(plant)  # (the call the rig made, by its name)
        if name == "snapshot":
            snaps.append(result)
            if len(snaps) > 8:  # (the rig holds one at a time: the older ones go, as in the run)
                snaps[-9] = None
        elif check and type(expected) is not tuple and result != expected:
            sys.exit(
                f"call {i} ({name}{tuple(kept)!r:.120}) gave {result!r:.200} on replay, expected the run's "
                f"{expected!r:.200}: the rig changed the plant outside its calls; its share is not measured"
            )
    return time.process_time() - t0


def measure(robot: str, sim_s: float, repeat: int, raw_us: float) -> dict:
    """The robot run ``repeat`` times for ``sim_s`` simulated s (after 1 s not counted) and its
    plant's calls replayed as many times: each figure the least, an exchange's µs."""
    spec = RigSpec(robot, seed=1, busy_poll=False, allow_exit=True)
    runs = []
    for _ in range(repeat):  # (the host's time, from runs of their own: the recording costs)
        with Rig(spec, Recording()) as rig:
            rig.run_for(1.0)
            n0, t0, fw0 = rig.stats.link_round_trips, resource.getrusage(resource.RUSAGE_SELF), bench._fw_cpu_s(rig)
            rig.run_for(sim_s)
            t1, exchanges = resource.getrusage(resource.RUSAGE_SELF), rig.stats.link_round_trips - n0
            fw_s = bench._fw_cpu_s(rig) - fw0
        runs.append((t1.ru_utime - t0.ru_utime, t1.ru_stime - t0.ru_stime, fw_s))
    user_s, system_s, _ = min(runs)
    fw_s = min(r[2] for r in runs)
    plant, _ = build_plant(spec, spec.resolve())
    recorded = RecordedPlant(plant)
    with Rig(spec, Recording(), plant=recorded) as rig:
        rig.run_for(1.0)
        start, n0 = len(recorded.calls), rig.stats.link_round_trips
        rig.run_for(sim_s)
        if rig.stats.link_round_trips - n0 != exchanges:
            sys.exit(f"expected the recorded run's {exchanges} exchanges again, got {rig.stats.link_round_trips - n0}")
    calls = recorded.calls
    replays = []
    for k in range(repeat):
        fresh, _ = build_plant(spec, spec.resolve())
        snaps = []
        replay(fresh, calls[:start], k == 0, snaps)
        replays.append(replay(fresh, calls[start:], k == 0, snaps))
    per = 1e6 / max(exchanges, 1)
    return {
        "robot": robot,
        "sim_s": sim_s,
        "repeat": repeat,
        "exchanges": exchanges,
        "plant_calls": len(calls) - start,
        "raw_us": raw_us,
        "host_us": user_s * per,
        "system_us": system_s * per,
        "plant_us": min(replays) * per,
        "fw_us": fw_s * per,
    }


def lines(m: dict, share: float) -> list[str]:
    """What :func:`measure` found, and what ``share`` of the exchange's floor leaves the host."""
    host_us, plant_us, repeat = m["host_us"], m["plant_us"], m["repeat"]
    floor_us = m["raw_us"] + m["fw_us"]
    budget_us = floor_us / share - floor_us
    return [
        f"host CPU an exchange (least of {repeat} runs): user {host_us:.1f} us, system {m['system_us']:.1f} us "
        f"(the pty's calls); the plant's own calls replayed: {plant_us:.1f} us (least of {repeat}; "
        f"{plant_us / host_us:.0%} of the host's user time); the rest of the user time (the rig, the link's Python, "
        f"the codec): {host_us - plant_us:.1f} us",
        f"an exchange's floor: raw round trip {m['raw_us']:.1f} us + the interpreter's CPU {m['fw_us']:.1f} us = "
        f"{floor_us:.1f} us; at {share:.0%} of it an exchange may take {floor_us / share:.1f} us, which "
        f"leaves the host {budget_us:.1f} us beyond the floor: the plant alone takes {plant_us / budget_us:.0%} of "
        f"that, the host's user time {host_us / budget_us:.0%}",
    ]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("robot", help="an app's name or a rig file (RigSpec's first argument)")
    parser.add_argument("sim_s", type=float, help="simulated seconds measured (after 1 s not counted)")
    parser.add_argument("--repeat", type=int, default=5, help="runs and replays timed (the least is printed)")
    parser.add_argument("--share", type=float, default=0.65, help="a share of the floor to set the host's time against")
    args = parser.parse_args(argv)
    m = measure(args.robot, args.sim_s, args.repeat, bench.percentile(bench.bench_raw(2000), 50))
    print(f"{args.robot}: {args.sim_s:g} simulated s, {m['exchanges']} exchanges, {m['plant_calls']} plant calls")
    for line in lines(m, args.share):
        print("  " + line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
