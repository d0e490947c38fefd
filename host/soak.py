"""``make soak``: a long lockstep run of the rover (24 simulated hours by default) that
shows memory stays flat on both sides of the link: ``python -m host.soak [--hours H]``.

It prints, at the start (after the first simulated minute, once the firmware and the
host have made what they keep) and at the end, and a line per simulated hour between:

- the host's resident memory (``VmRSS`` of ``/proc/self/status``) and its peak (``VmHWM``);
- the firmware process's resident memory (``VmRSS`` of ``/proc/<pid>/status``, the unix
  port the rig started) and its open file descriptors. MicroPython's own heap figures
  (``gc.mem_free()``, ``micropython.mem_info()``) exist only inside the firmware, which a
  soak must not change; the unix port's GC heap is one block allocated at start
  (``-X heapsize``), so a leak of MicroPython objects ends the run with the firmware's
  ``MemoryError`` (a failed soak), and a leak outside it shows as resident memory;
- each budget's count and how many histogram entries hold it (docs/budgets.md).

Exit status 1 if the run failed or either process's resident memory grew by more than
``--max-growth-mb`` (default 8 MB) from the start to the end.
"""

import argparse
import os
import sys
import time
from dataclasses import dataclass

from host.core.errors import HarnessError
from host.link.transport import busy_poll_wanted
from host.rig import Rig, RigSpec

STEP_S = 60.0
WARM_UP_S = 60.0
MB = 1024.0


def proc_status(pid: int | str = "self") -> dict[str, int]:
    """The memory lines of /proc/<pid>/status in kB (VmRSS, VmHWM), {} if the process is gone."""
    out = {}
    try:
        with open(f"/proc/{pid}/status", encoding="ascii") as f:
            for line in f:
                key, _, rest = line.partition(":")
                if key in ("VmRSS", "VmHWM"):
                    out[key] = int(rest.split()[0])
    except (FileNotFoundError, ProcessLookupError):
        return {}
    return out


def firmware_pid(rig) -> int | None:
    proc = getattr(rig.target, "proc", None)
    return proc.pid if proc is not None else None


@dataclass
class Sample:
    sim_s: float
    wall_s: float
    host_rss_kb: int
    host_hwm_kb: int
    fw_rss_kb: int | None
    fw_fds: int | None

    @classmethod
    def take(cls, rig, wall_s: float) -> "Sample":
        host = proc_status()
        pid = firmware_pid(rig)
        fw = proc_status(pid) if pid is not None else {}
        try:
            fds = len(os.listdir(f"/proc/{pid}/fd")) if pid is not None else None
        except OSError:
            fds = None
        return cls(rig.t_us / 1e6, wall_s, host["VmRSS"], host["VmHWM"], fw.get("VmRSS"), fds)

    def line(self) -> str:
        fw = f"{self.fw_rss_kb / MB:6.1f} MB" if self.fw_rss_kb is not None else "     n/a"
        rtf = self.sim_s / self.wall_s if self.wall_s > 0 else 0.0
        return (
            f"  {self.sim_s / 3600:5.2f} h  wall {self.wall_s / 60:6.1f} min  {rtf:4.0f}x  "
            f"host RSS {self.host_rss_kb / MB:6.1f} MB (peak {self.host_hwm_kb / MB:6.1f})  "
            f"firmware RSS {fw}  fds {self.fw_fds if self.fw_fds is not None else 'n/a'}"
        )


def soak(hours: float, seed: int, show=print) -> tuple[Sample, Sample, Rig]:
    """Run the rover for ``hours`` simulated hours; (start sample, end sample, stopped rig)."""
    end_s = hours * 3600
    rig = Rig(RigSpec("rover", seed=seed, busy_poll=busy_poll_wanted()))
    tty = sys.stdout.isatty()
    with rig:
        t0 = time.perf_counter()
        rig.run_for(min(WARM_UP_S, end_s))
        start = Sample.take(rig, time.perf_counter() - t0)
        show(f"start (after {min(WARM_UP_S, end_s):g} simulated s):")
        show(start.line())
        next_line_s = 3600.0
        while rig.t_us < end_s * 1e6:
            rig.run_for(min(STEP_S, end_s - rig.t_us / 1e6))
            sim_s = rig.t_us / 1e6
            if sim_s >= next_line_s or sim_s >= end_s:
                if tty:
                    sys.stdout.write("\r\x1b[K")
                show(Sample.take(rig, time.perf_counter() - t0).line())
                next_line_s += 3600.0
            elif tty:
                wall = time.perf_counter() - t0
                sys.stdout.write(f"\r\x1b[K  {sim_s / 3600:5.2f} / {hours:g} simulated h, {sim_s / wall:.0f}x")
                sys.stdout.flush()
        end = Sample.take(rig, time.perf_counter() - t0)
    return start, end, rig


def report(start: Sample, end: Sample, rig, max_growth_mb: float, show=print) -> bool:
    """Print the start, the end and the growth; True if within ``max_growth_mb``."""
    show(f"soak: rover, seed {rig.seed}, {end.sim_s / 3600:g} simulated h in {end.wall_s / 60:.1f} wall min")
    rows = [("host RSS", start.host_rss_kb, end.host_rss_kb), ("firmware RSS", start.fw_rss_kb, end.fw_rss_kb)]
    show(f"  {'':14}{'start':>12}{'end':>12}{'growth':>12}")
    ok = True
    for name, a, b in rows:
        if a is None or b is None:
            show(f"  {name:14}{'n/a':>12}{'n/a':>12}")
            continue
        growth = (b - a) / MB
        ok = ok and growth <= max_growth_mb
        show(f"  {name:14}{a / MB:9.1f} MB{b / MB:9.1f} MB{growth:+9.1f} MB")
    show(
        f"  host peak RSS {end.host_hwm_kb / MB:.1f} MB; "
        f"firmware fds {start.fw_fds} at the start, {end.fw_fds} at the end"
    )
    for name, budget in rig.budgets.items():
        stats = budget.stats()
        show(
            f"  budget {name}: {stats['count']} values in {len(budget.histogram)} histogram entries, "
            f"{stats['misses']} misses (p50 {stats['p50']}, max {stats['max']} us)"
        )
    counters = getattr(rig, "counters", None)
    if callable(counters):
        show(f"  link: {counters()}")
    show(f"  growth {'within' if ok else 'OVER'} {max_growth_mb:g} MB")
    return ok


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m host.soak", description=__doc__.split("\n")[0])
    parser.add_argument("--hours", type=float, default=24.0, help="simulated hours of the rover (default 24)")
    parser.add_argument("--seed", type=int, default=1, help="the plant's seed (default 1)")
    parser.add_argument("--max-growth-mb", type=float, default=8.0, help="allowed RSS growth, host or firmware (8)")
    args = parser.parse_args(argv)
    if not 0 < args.hours <= 240:
        parser.error(f"argument --hours: expected 0 < hours <= 240, got {args.hours:g}")
    print(f"soak: the rover for {args.hours:g} simulated hours in lockstep, seed {args.seed}", flush=True)
    try:
        start, end, rig = soak(args.hours, args.seed, show=lambda text: print(text, flush=True))
    except HarnessError as e:
        print(f"soak: the run failed: {type(e).__name__}: {e}", file=sys.stderr)
        return 1
    return 0 if report(start, end, rig, args.max_growth_mb) else 1


if __name__ == "__main__":
    raise SystemExit(main())
