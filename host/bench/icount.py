"""The firmware's instructions a simulated second in a bench robot, counted by valgrind
(docs/bench.md, "The interpreter we build"): which load does not change, so two builds or
two versions of the shim compare on a busy machine.

    PYTHONPATH=. python host/bench/icount.py rover 5 45 [--binary PATH] [--tool cachegrind]
    PYTHONPATH=. python host/bench/icount.py enc10k 1 3
    PYTHONPATH=. python host/bench/icount.py pio10k 1 2
    PYTHONPATH=. python host/bench/icount.py imu 1 3

The robot runs twice, SHORT and LONG simulated seconds (the rover with seed 1; the encoder
bot at 10,000 edges a second, ``enc40k`` at 40,000, its counts checked against the plant's
edges; ``pio10k`` the PIO decoder robot, its counts checked too; ``imu`` the bus-heavy
robot), the interpreter under valgrind (callgrind by default) and without the sandbox; the instructions of each run and
(LONG - SHORT) / (LONG - SHORT seconds) are printed: the start-up (about 280 M
instructions, most of it compiling the shim) cancels out. A run's count repeats to a few
thousand instructions.
"""

import argparse
import os
import signal
import subprocess
import sys
import tempfile
from pathlib import Path

import host.bench as bench
from host.core import interpreter
from host.rig import Recording, Rig, RigSpec
from host.rig.targets import target as rig_target

WATCHDOG_S = 600.0  # the interpreter runs some 50 times slower under valgrind


def _end_by_sigterm(end):
    """valgrind writes its counts when the process exits: SIGTERM it (the rig's SIGKILL
    would lose them), then end it as the rig does."""

    def ended(proc):
        if proc.poll() is None:
            try:
                os.killpg(proc.pid, signal.SIGTERM)
                proc.wait(timeout=60)
            except (ProcessLookupError, subprocess.TimeoutExpired):
                pass
        end(proc)

    return ended


def instructions(folder: Path) -> int:
    """The largest count among the out files (the run's interpreter; a version probe is small)."""
    counts = [0]
    for f in folder.glob("out.*"):
        for line in f.read_text(errors="replace").splitlines():
            if line.startswith(("summary:", "totals:")):
                counts.append(int(line.split()[1]))
    return max(counts)


def run(workload: str, sim_s: float, binary: str, tool: str) -> int:
    with tempfile.TemporaryDirectory(prefix="mpy-fil-icount-") as tmp:
        wrapper = Path(tmp) / "micropython"
        extra = "--cache-sim=no " if tool == "cachegrind" else ""
        valgrind = f"valgrind -q --tool={tool} {extra}--{tool}-out-file={tmp}/out.%p"
        wrapper.write_text(f'#!/bin/sh\nexec {valgrind} {binary} "$@"\n')
        wrapper.chmod(0o755)
        os.environ["MICROPYTHON"] = str(wrapper)
        os.environ["MPY_FIL_SANDBOX"] = "off"
        if workload == "rover":
            with Rig(RigSpec("rover", seed=1, watchdog_s=WATCHDOG_S), Recording()) as rig:
                rig.run_for(sim_s)
        elif workload == "imu":  # (the bus-heavy robot; MPY_FIL_BUS_IMAGES=0 or 1 compares the two ways)
            r = bench.run_imu_bot(round(sim_s * 1000), watchdog_s=WATCHDOG_S)
            if not (r["printed"] or "").startswith("imu_bot "):
                sys.exit(f"expected the robot's summary, got {r['printed']!r}")
        elif workload == "pio10k":  # (the PIO decoder robot; MPY_FIL_PIO_AHEAD=0 or 1 compares the two ways)
            r = bench.run_pio_bot(round(sim_s * 1000), watchdog_s=WATCHDOG_S)
            if r["counts"] != r["edges"]:
                sys.exit(f"expected the firmware's counts to equal the plant's edges {r['edges']}, got {r['counts']}")
        else:
            rate = int(workload[3:].replace("k", "000"))
            run_ms = round(sim_s * 1000)
            main_dir = bench.encoder_firmware(Path(tmp) / "fw", rate, run_ms)
            rig_file = str(bench.ENCODER_BOT / "rig.toml")
            spec = RigSpec(rig_file, seed=1, main_dir=main_dir, allow_exit=True, watchdog_s=WATCHDOG_S)
            with Rig(spec, Recording()) as rig:
                rig.run_for(run_ms / 1000 + 0.5)
                truth = rig.truth()
                counts = [line for line in rig.console.splitlines() if line.startswith("counts ")]
                edges = (truth["enc_l_edges"], truth["enc_r_edges"])
                got = tuple(int(c) for c in counts[-1].split()[1:]) if counts else None
                if got != edges:
                    sys.exit(f"expected the firmware's counts to equal the plant's edges {edges}, got {got}")
        return instructions(Path(tmp))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("workload", choices=("rover", "enc10k", "enc40k", "pio10k", "imu"))
    parser.add_argument("short", type=float, help="simulated s of the first run")
    parser.add_argument("long", type=float, help="simulated s of the second run")
    parser.add_argument("--binary", help="the interpreter (default: the harness's)")
    parser.add_argument("--tool", default="callgrind", choices=("callgrind", "cachegrind"))
    args = parser.parse_args(argv)
    binary = str(Path(args.binary or interpreter.find()).resolve())
    rig_target.end_process = _end_by_sigterm(rig_target.end_process)
    short = run(args.workload, args.short, binary, args.tool)
    long_ = run(args.workload, args.long, binary, args.tool)
    per_s = (long_ - short) / (args.long - args.short)
    print(
        f"{args.workload} {binary}: {short:,} instructions in {args.short:g} simulated s, {long_:,} in "
        f"{args.long:g}; {per_s / 1e6:.2f} M a simulated s"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
