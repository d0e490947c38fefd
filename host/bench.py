"""Wall-clock figures of the core loop: ``python -m host.bench`` (``make bench``).

- raw pty round trip: CPython writes an empty STATE's worth of bytes, MicroPython's unix
  port answers an OUT and a WAIT's worth, nothing decoded (:mod:`host.link.rawpingpong`).
  It is measured in the same run, before and after the rest, and every figure below is
  also given as a ratio to it, with the limit it implies for the rover: 50 ms / (raw
  round trip + the firmware's own compute per step);
- lockstep real-time factor: simulated seconds per wall second for 10 simulated minutes
  of the rover firmware at 50 ms control quanta;
- link round trip: host sends STATE -> shim answers WAIT, p50/p99 in microseconds,
  measured with a firmware that does nothing but toggle a pin and sleep;
- duct robot: its single right branch run, bound by the cost of an exchange (a 160 Hz
  timer, slot encoders, a record stream): real-time factor, exchanges per simulated
  second and their cost;
- pool cleaner mission: the whole 25 x 8 m pool (about an hour simulated) from start to
  "done", its real-time factor, unrecorded and then recorded as ``make hil`` records it
  (trace folder and link log, in a child process: its wall time, peak memory, bytes on disk);
- encoder-heavy robot (``host/bench/encoder_bot``): Pico motor-control firmware counting
  every edge of two quadrature encoders (28 counts a motor turn, 98.5:1 gearboxes) in
  ``Pin.irq`` handlers, a velocity PID in a ``Timer`` callback, at 10,000 and 40,000 edges
  a second, its edges as EDGES segments (``--per-edge-encoders``: also a STATE change an
  edge, as before them): real-time factor, wall us per edge, the host's and the firmware's
  CPU an edge, and the same handler's bare cost in a MicroPython loop (the limit), measured
  in the same run, with the ratio;
- PIO decoder robot (``host/bench/pio_bot``): a Pico robot whose two wheels (about 10,000
  edges a second together) are counted by PIO quadrature decoders, each read by request every
  10 ms as the SDK's ``quadrature_encoder_get_count`` reads it (``rx_fifo()``, the old counts
  taken, a fresh ``get()``): real-time factor, exchanges a simulated second, the PIO frames
  answered ahead (``MPY_FIL_PIO_AHEAD``), the counts against the plant's edges, its floor;
- bus-heavy robot (``host/bench/imu_bot``): a Pico robot holding its heading on an LSM6DSOX
  read from a 208 Hz ``Timer`` (STATUS_REG polled for data-ready, then 12 bytes of gyro and
  accelerometer with ``readfrom_mem_into``) and steering away from walls seen by a VL53L0X
  polled for its result: real-time factor, bus transfers and link exchanges a simulated
  second, the reads answered in the board from the bus images (``MPY_FIL_BUS_IMAGES``), and
  its floor (its exchanges at the raw round trip plus the same driver code's bare
  cost in a MicroPython loop against a stub bus).
These are measurements, not pass/fail tests; the target figures are printed beside them,
each with the FLOOR measured in the same run: the best real-time factor the lockstep
protocol allows on this machine, from terms measured in the run (:func:`floor_rtf`;
docs/clock.md says how each is computed), and whether the target is above it.
"""

import argparse
import functools
import json
import math
import os
import resource
import statistics
import struct
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from host.core import children, interpreter
from host.core.drivers import DriverMissing, driver_folder
from host.core.paths import REPO
from host.link import frames as F
from host.link import rawpingpong
from host.link.transport import busy_poll_wanted
from host.rig import Recording, Rig, RigSpec
from host.rig.hardware import busimage, pio_ahead
from host.rig.loop.clock import EDGE_SEGMENTS_ENV
from host.rig.loop.pacing import Lockstep
from host.rig.loop.waits import ExpectTimeout
from host.rig.targets import sandbox

PING = Path(__file__).parent / "tests" / "firmware" / "ping"
ENCODER_BOT = Path(__file__).parent / "bench" / "encoder_bot"
IMU_BOT = Path(__file__).parent / "bench" / "imu_bot"
IMU_TARGET = 50.0  # issue 45: x real time on a quiet machine (and >= 50 % of the floor)
PIO_BOT = Path(__file__).parent / "bench" / "pio_bot"
PIO_READ_MS = 10  # issue 45: each PIO decoder read by request every 10 ms, at 10,000 edges a second
PIO_FLOOR_SHARE = 0.40  # ... at >= 40 % of its floor
PIO_TITLE = "PIO decoder robot (host/bench/pio_bot: two PIO quadrature decoders read by request every 10 ms):"
ENCODER_RATES = (10_000, 40_000)  # edges a second, both wheels together
STEP_US = 50_000  # the rover's control quantum
ROVER_TARGET = POOL_TARGET = 400.0  # issue 30's real-time factors
ENCODER_TARGET = 100.0  # at 10,000 edges a second
STATE_WAIT_TARGET = 1.6  # issue 45: STATE -> WAIT over the raw round trip
KIT_TARGET = 20.0  # issue 44: each kit's demo, x real time on a quiet machine
KIT_SIM_S = 15.0  # a kit's demo runs until it ends, or this long
HIL_FIRMWARE = REPO / "hil_tests" / "firmware"
KIT_DEMOS = (
    # (kit, (folder of hil_tests/firmware, where it goes in the firmware folder) ..., the button
    # pressed from 0.2 to 0.3 s, a pinned driver beside main.py, what it prints last); a kit
    # without a demo of ours: the firmware of its written test (host/kits/<kit>/test.py)
    ("xrp_beta", (("kits/xrp", "."),), "user_button", None, "done"),
    ("xrp", (("kits/xrp", "."),), "user_button", None, "done"),
    ("pololu_3pi_2040", (("kits/pololu_3pi_2040", "."), ("kitbot/lib", "lib")), "button_b", None, "done"),
    ("kitronik_buggy", (("kits/kitronik_buggy", "."),), "button", "kitronikpicoautonomousroboticsplatform", "done"),
    ("cytron_maker_pi_rp2040", (), "button_1", None, "range_after"),
    ("sunfounder_pico_4wd", (), None, None, "done"),
    ("keyestudio_beetlebot", (), None, None, "range_after"),
)
STATE_BYTES = F.HEADER_LEN + F.CRC_LEN + F.STATE_LEN  # an empty STATE
REPLY_BYTES = 2 * (F.HEADER_LEN + F.CRC_LEN) + struct.calcsize(F.OUT_FMT) + F.WAIT_LEN  # an OUT and a WAIT


def floor_rtf(
    exchanges_per_s: float, raw_us: float, compute_us_per_s: float = 0.0, edges_per_s: float = 0.0, bare_us: float = 0.0
) -> float:
    """The best real-time factor a lockstep run allows: each simulated second costs at least
    its exchanges at the raw pty round trip, the firmware's own compute, and each edge's bare
    handler; the rest (the host's plant, the codec, the shim) counts as nothing."""
    wall_us = exchanges_per_s * raw_us + compute_us_per_s + edges_per_s * bare_us
    return math.inf if wall_us <= 0 else 1e6 / wall_us


def floor_text(floor: float, target: float, unit: str = "x real time") -> str:
    """The floor beside a target: a real-time factor target above the floor cannot be reached."""
    verdict = "reachable" if floor >= target else "beyond the floor"
    return f"floor: {floor:.0f}{unit} (target {target:g}{unit.split()[0]}: {verdict})"


def ratio_floor_text(floor_ratio: float, target_ratio: float) -> str:
    """The same for a ratio to the raw round trip, where lower is better."""
    verdict = "reachable" if floor_ratio <= target_ratio else "beyond the floor"
    return f"floor: {floor_ratio:.2f}x raw (target <= {target_ratio:g}x: {verdict})"


def compute_us_total(budget_stats_histogram: dict) -> int:
    """The firmware's compute over a run: the sum of every wake's ``control.compute``."""
    return sum(value * n for value, n in budget_stats_histogram.items())


def percentile(values, pct):
    values = sorted(values)
    return values[min(len(values) - 1, int(pct / 100 * len(values)))]


def bench_raw(n: int = 5000) -> list[float]:
    """The pty's own round trip with the link's frame sizes and the link's way of waiting."""
    busy_poll_s = Lockstep().busy_poll_s(busy_poll_wanted())
    return rawpingpong.round_trips_us(str(interpreter.find()), n, STATE_BYTES, REPLY_BYTES, busy_poll_s)


def bench_rover(sim_s: float) -> dict:
    with Rig(RigSpec("rover", seed=1, busy_poll=busy_poll_wanted()), Recording(time_round_trips=True)) as rig:
        fw0, cpu0 = _fw_cpu_s(rig), time.process_time()
        t0 = time.perf_counter()
        step = 60.0
        done = 0.0
        while done < sim_s:
            rig.run_for(min(step, sim_s - done))
            done = rig.t_us / 1e6
            print(f"  rover: {done:6.0f} / {sim_s:.0f} simulated s", end="\r", flush=True)
        wall = time.perf_counter() - t0
        fw, cpu = _fw_cpu_s(rig) - fw0, time.process_time() - cpu0
        print()
        return {
            "sim_s": sim_s,
            "wall_s": wall,
            "rtf": sim_s / wall,
            "host_cpu_s": cpu,
            "fw_cpu_s": fw,
            "round_trips": rig.stats.link_round_trips,
            "wake_rtt": rig.stats.round_trip_us,
            "control": rig.budgets["control.period"].stats(),
            "compute": rig.budgets["control.compute"].stats(),
            "compute_total_us": compute_us_total(rig.budgets["control.compute"].histogram),
        }


BOARDS_RIG = """\
name = "two_boards_bench"
[plant]
body = "bench"
[[plant.parts]]
kind = "board_uart"
name = "link"
[[boards]]
name = "a"
firmware = { dir = "a" }
board = { family = "esp32", pins = { LINK_UART = 1 } }
wiring = { LINK_UART = "link.a" }
[[boards]]
name = "b"
firmware = { dir = "b" }
board = { family = "rpi_pico", pins = { LINK_UART = 0 } }
wiring = { LINK_UART = "link.b" }
"""
BOARDS_FIRMWARE = """\
import time
from machine import UART
u = UART(ID, 115200)
n = 0
while True:
    u.write(b"%d\\n" % n)  # (a line to the other board every 10 ms, what came from it read)
    n += 1
    u.read()
    time.sleep_ms(10)
"""


def bench_boards(sim_s: float = 10.0) -> dict:
    """Issue 47's speed case: two boards on one clock, each sending the other a line every
    10 ms over a board_uart (docs/multi-board.md); its real-time factor and exchanges."""
    from host.rig.config.boardfile import load_boards
    from host.rig.loop.boardset import BoardSet

    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for board, uart in (("a", 1), ("b", 0)):
            (folder / board).mkdir()
            (folder / board / "main.py").write_text(BOARDS_FIRMWARE.replace("ID", str(uart)))
        (folder / "rig.toml").write_text(BOARDS_RIG)
        with BoardSet(load_boards(folder / "rig.toml"), seed=1) as boards:
            fw0, cpu0 = sum(map(_fw_cpu_s, boards.rigs.values())), time.process_time()
            t0 = time.perf_counter()
            boards.run_for(sim_s)
            wall = time.perf_counter() - t0
            fw, cpu = sum(map(_fw_cpu_s, boards.rigs.values())) - fw0, time.process_time() - cpu0
            exchanges = sum(r.stats.link_round_trips for r in boards.rigs.values())
            rounds = boards.rounds
    return {
        "sim_s": sim_s,
        "wall_s": wall,
        "rtf": sim_s / wall,
        "exchanges": exchanges,
        "rounds": rounds,
        "host_cpu_s": cpu,
        "fw_cpu_s": fw,
    }


def report_boards(boards: dict, rover: dict | None) -> None:
    share = f"; {boards['rtf'] / rover['rtf']:.0%} of the rover's in this run (issue 47 asks >= 50 %)" if rover else ""
    print(
        f"  two boards, a line each way every 10 ms: {boards['rtf']:.1f}x real time ({boards['sim_s']:g} simulated s "
        f"in {boards['wall_s']:.2f} wall s){share}; {boards['exchanges'] / boards['sim_s']:.0f} link exchanges a "
        f"simulated s, both boards, in {boards['rounds'] / boards['sim_s']:.0f} rounds"
    )
    print(
        f"  CPU a simulated s: host {boards['host_cpu_s'] / boards['sim_s'] * 1e3:.1f} ms, the boards' interpreters "
        f"{boards['fw_cpu_s'] / boards['sim_s'] * 1e3:.1f} ms (CPU time: what the machine's load does not change)"
    )


def bench_duct(seed: int = 3, limit_s: float = 90.0) -> dict:
    """The duct robot's single right branch run (make hil's sweeps are mostly these): bound
    by the cost of an exchange, not of a control step (docs/clock.md)."""
    with Rig(RigSpec("duct", seed=seed, busy_poll=busy_poll_wanted()), Recording(time_round_trips=True)) as rig:
        t0 = time.perf_counter()
        while "explored:" not in rig.console and rig.t_us < limit_s * 1e6:
            rig.run_for(2.0)
        wall = time.perf_counter() - t0
        return {
            "sim_s": rig.t_us / 1e6,
            "wall_s": wall,
            "round_trips": rig.stats.link_round_trips,
            "state_wait": rig.stats.round_trip_us,
        }


def bench_pool(limit_s: float = 75 * 60, artefacts: Path | None = None) -> dict:
    record = artefacts is not None
    with Rig(
        RigSpec("pool_cleaner", seed=1, busy_poll=busy_poll_wanted()),
        Recording(record=record, trace=record, artefacts=artefacts),
    ) as rig:
        t0 = time.perf_counter()
        while "done:" not in rig.console and rig.t_us < limit_s * 1e6:
            rig.run_for(60.0)
            print(f"  pool cleaner: {rig.t_us / 60e6:4.0f} simulated min", end="\r", flush=True, file=sys.stderr)
        wall = time.perf_counter() - t0
    wall_stop = time.perf_counter() - t0  # (a recorded run writes its trace folder at stop)
    print(file=sys.stderr)
    sim_s = rig.t_us / 1e6
    return {
        "sim_s": sim_s,
        "wall_s": wall_stop,
        "run_wall_s": wall,
        "rtf": sim_s / wall_stop,
        "done": "done:" in rig.console,
        "round_trips": rig.stats.link_round_trips,
        "coverage": rig.truth()["coverage_fraction"],
        "compute_total_us": compute_us_total(rig.budgets["control.compute"].histogram),
    }


def bench_pool_recorded() -> dict:
    """The recorded mission in a child process, so that its peak memory is its own."""
    with tempfile.TemporaryDirectory(prefix="mpy-fil-bench-") as tmp:
        cmd = [sys.executable, "-m", f"{__package__}.bench", "--recorded-pool-child", tmp]
        out = subprocess.run(cmd, check=True, stdout=subprocess.PIPE, text=True, **children.popen_options()).stdout
        result = json.loads(out.strip().splitlines()[-1])
        result["disk_mb"] = sum(p.stat().st_size for p in Path(tmp).rglob("*") if p.is_file()) / 1e6
        return result


def _recorded_pool_child(folder: str) -> int:
    result = bench_pool(artefacts=Path(folder) / "pool")
    result["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(json.dumps(result))
    return 0


def encoder_firmware(folder: Path, edges_per_s: int, run_ms: int) -> Path:
    """A copy of the encoder robot's firmware in ``folder`` whose config.py drives both
    wheels at ``edges_per_s`` edges a second together, for ``run_ms``."""
    folder.mkdir(parents=True, exist_ok=True)
    for name in ("main.py", "encoder.py"):
        (folder / name).write_bytes((ENCODER_BOT / name).read_bytes())
    (folder / "config.py").write_text(f"TARGET_CPS = {edges_per_s // 2}\nRUN_MS = {run_ms}\n")
    return folder


def run_encoder_bot(edges_per_s: int, run_ms: int, seed: int = 1, segments: bool | None = None, **recording) -> dict:
    """The encoder robot driven for ``run_ms`` at ``edges_per_s``, braked, and run to its end:
    the firmware's counts, the plant's edges, the wall time, the host's and the firmware's
    CPU. ``segments``: its edges as EDGES segments (True) or a change each (False; None: as
    the rig goes by default, ``host.rig.loop.clock.edge_segments_wanted``)."""
    if segments is None:
        return _run_encoder_bot(edges_per_s, run_ms, seed, **recording)
    was = os.environ.get(EDGE_SEGMENTS_ENV)
    os.environ[EDGE_SEGMENTS_ENV] = "1" if segments else "0"
    try:
        return _run_encoder_bot(edges_per_s, run_ms, seed, **recording)
    finally:
        if was is None:
            del os.environ[EDGE_SEGMENTS_ENV]
        else:
            os.environ[EDGE_SEGMENTS_ENV] = was


def _proc_cpu_s(pid: int) -> float:
    """A process's CPU time so far (user + system), from /proc (0.0 where there is none)."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:
        return 0.0
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def _run_encoder_bot(edges_per_s: int, run_ms: int, seed: int, **recording) -> dict:
    with tempfile.TemporaryDirectory(prefix="mpy-fil-bench-") as tmp:
        main_dir = encoder_firmware(Path(tmp) / "fw", edges_per_s, run_ms)
        spec = RigSpec(str(ENCODER_BOT / "rig.toml"), seed=seed, main_dir=main_dir, allow_exit=True)
        with Rig(spec, Recording(**recording)) as rig:
            t0 = time.perf_counter()
            warm_s = min(0.5, run_ms / 2000)  # (the CPU an edge is read past the start, to the driving's end)
            rig.run_for(warm_s)
            cpu0, fw0, edges0 = time.process_time(), _fw_cpu_s(rig), _plant_edges(rig)
            rig.run_for(run_ms / 1000 - warm_s)
            cpu1, fw1, edges1 = time.process_time(), _fw_cpu_s(rig), _plant_edges(rig)
            rig.run_for(0.5)  # (the firmware brakes, prints its counts and ends)
            wall = time.perf_counter() - t0
            truth = rig.truth()
            counts = [line for line in rig.console.splitlines() if line.startswith("counts ")]
            result = {
                "sim_s": rig.t_us / 1e6,
                "wall_s": wall,
                "counts": tuple(int(c) for c in counts[-1].split()[1:]) if counts else None,
                "edges": (truth["enc_l_edges"], truth["enc_r_edges"]),
                "round_trips": rig.stats.link_round_trips,
                "segments": rig.stats.edge_segments,
            }
    driven = max(1, edges1 - edges0)
    result["host_us_edge"] = (cpu1 - cpu0) * 1e6 / driven
    result["fw_us_edge"] = (fw1 - fw0) * 1e6 / driven if fw0 and fw1 else 0.0  # (0.0: not there to read)
    return result


def _fw_cpu_s(rig) -> float:
    proc = rig.target.proc
    return _proc_cpu_s(sandbox.interpreter_pid(proc)) if proc is not None else 0.0


def _plant_edges(rig) -> int:
    truth = rig.plant.truth()
    return truth["enc_l_edges"] + truth["enc_r_edges"]


BARE_HANDLER = """
import sys, time
class Pin:
    IN = 0; PULL_UP = 1; IRQ_RISING = 1; IRQ_FALLING = 2
    def __init__(self, id, *a): self.v = 0
    def value(self): return self.v
    def irq(self, **kw): pass
class machine: Pin = Pin
sys.modules["machine"] = machine
sys.path.insert(0, %r)
from encoder import QuadEncoder
enc = QuadEncoder(2, 3)
a, b, on_a, on_b = enc.a, enc.b, enc.on_a, enc.on_b
def edges(n, call):
    t0 = time.ticks_us()
    for i in range(n):
        a.v = 1; call and on_a(a); b.v = 1; call and on_b(b); a.v = 0; call and on_a(a); b.v = 0; call and on_b(b)
    return time.ticks_diff(time.ticks_us(), t0)
best = min(edges(%d, True) - edges(%d, False) for _ in range(5))
print(best / (4 * %d), enc.count)
"""


def bare_handler_us(quads: int = 50_000) -> float:
    """The encoder's handlers called in a bare MicroPython loop (no shim, no link): wall us an
    edge, the loop's own cost taken off; the best of 5."""
    out = _bare(BARE_HANDLER % (str(ENCODER_BOT), quads, quads, quads))
    return float(out.split()[0])


def _bare(script: str) -> str:
    """What ``script`` prints, run by the harness's MicroPython alone (no shim, no link)."""
    return subprocess.run(
        [str(interpreter.find()), "-c", script],
        check=True,
        stdout=subprocess.PIPE,
        text=True,
        **children.popen_options(),
    ).stdout


def bench_encoders(run_ms: int = 10_000, per_edge: bool = False) -> dict:
    """Both edge rates, their edges as segments (and, with ``per_edge``, a change each: the
    run before it, alternated with it), then the bare handler."""
    runs = {}
    for rate in ENCODER_RATES:
        runs[rate] = run_encoder_bot(rate, run_ms, segments=True)
        if per_edge:
            runs[f"{rate:,} edges/s, a change an edge"] = run_encoder_bot(rate, run_ms, segments=False)
    return {"runs": runs, "bare_us": bare_handler_us()}


def encoder_floor_line(run: dict, rate: int, raw_us: float, bare_us: float) -> str:
    """The encoder run's floor: its exchanges at the raw round trip plus each edge's bare
    handler (the Timer PID's own compute is left out: the floor is, if anything, too high)."""
    per_s = run["round_trips"] / run["sim_s"]
    edges_per_s = sum(run["edges"]) / run["sim_s"]
    floor = floor_rtf(per_s, raw_us, 0.0, edges_per_s, bare_us)
    head = floor_text(floor, ENCODER_TARGET) if rate == ENCODER_RATES[0] else f"floor: {floor:.0f}x real time"
    if not isinstance(rate, int):  # (the per-edge run: its own floor, with its own exchanges)
        head = f"floor: {floor:.0f}x real time"
    return (
        f"{head} = 1 s / ({per_s:.0f} exchanges x raw {raw_us:.0f} us + {edges_per_s:,.0f} edges x bare "
        f"{bare_us:.2f} us) a simulated s; reached {run['sim_s'] / run['wall_s'] / floor:.0%}"
    )


def report_encoders(enc: dict, raw_us: float) -> None:
    bare_us = enc["bare_us"]
    for rate, run in enc["runs"].items():
        edges = sum(run["edges"])
        per_edge_us = run["wall_s"] * 1e6 / edges
        same = (
            "counts = plant's edges" if run["counts"] == run["edges"] else f"COUNTS {run['counts']} != {run['edges']}"
        )
        how = f"{rate:,} edges/s" if isinstance(rate, int) else rate
        how += f" ({run['segments']:,} segments)" if run.get("segments") else ""
        print(
            f"  {how}: {run['sim_s'] / run['wall_s']:.1f}x real time (target >= 100x), {edges} edges in "
            f"{run['wall_s']:.2f} wall s: {per_edge_us:.2f} us an edge = {per_edge_us / bare_us:.0f}x the bare "
            f"handler; {run['round_trips'] / run['sim_s']:.0f} exchanges per simulated s; {same}"
        )
        if run.get("fw_us_edge"):
            print(
                f"    CPU an edge (past the first 0.5 simulated s, to the driving's end): host "
                f"{run['host_us_edge']:.2f} us, firmware {run['fw_us_edge']:.2f} us"
            )
        print(f"    {encoder_floor_line(run, rate, raw_us, bare_us)}")
    print(f"  bare handler in a MicroPython loop (the limit): {bare_us:.2f} us an edge")


def run_imu_bot(run_ms: int = 10_000, seed: int = 1, watchdog_s: float | None = None, **recording) -> dict:
    """The bus-heavy robot driven for ``run_ms``: its wall and CPU time (the host's and, once
    it has ended, the interpreter's), its bus transfers and link exchanges (those the shim
    answered from the bus images: ``bus_local``), what it printed."""
    with tempfile.TemporaryDirectory(prefix="mpy-fil-bench-") as tmp:
        main_dir = Path(tmp) / "fw"
        main_dir.mkdir()
        for name in ("main.py", "lsm6dsox.py", "vl53l0x.py"):
            (main_dir / name).write_bytes((IMU_BOT / name).read_bytes())
        (main_dir / "config.py").write_text(f"RUN_MS = {run_ms}\n")
        more = {"watchdog_s": watchdog_s} if watchdog_s else {}  # (longer under valgrind: host/bench/icount.py)
        spec = RigSpec(str(IMU_BOT / "rig.toml"), seed=seed, main_dir=main_dir, allow_exit=True, **more)
        transfers = [0]

        def count(_tx) -> None:
            transfers[0] += 1

        with Rig(spec, Recording(**recording)) as rig:
            rig.bus_trace.hooks.setdefault("i2c0", []).append(count)
            fw_cpu0, cpu0, t0 = firmware_cpu_s(rig), time.process_time(), time.perf_counter()
            rig.run_for(run_ms / 1000 - 0.05)  # (the interpreter's CPU read while it runs)
            fw_cpu = firmware_cpu_s(rig) - fw_cpu0
            rig.run_for(0.15)
            wall, cpu = time.perf_counter() - t0, time.process_time() - cpu0
            lines = [line for line in rig.console.splitlines() if line.startswith("imu_bot ")]
            result = {
                "sim_s": rig.t_us / 1e6,
                "wall_s": wall,
                "host_cpu_s": cpu,
                "firmware_cpu_s": fw_cpu,
                "transfers": transfers[0],
                "state_exchanges": rig.stats.link_round_trips,
                "bus_exchanges": rig.stats.bus_round_trips,
                "bus_local": rig.stats.bus_local,
                "printed": lines[-1] if lines else None,
            }
        result["exchanges"] = result["state_exchanges"] + result["bus_exchanges"]
        return result


def run_pio_bot(
    run_ms: int = 10_000, read_ms: int = PIO_READ_MS, seed: int = 1, watchdog_s: float | None = None, **recording
) -> dict:
    """The PIO decoder robot (``host/bench/pio_bot``): both wheels at about 10,000 edges a
    second together for ``run_ms``, each decoder read by request every ``read_ms``, then
    stopped: wall and CPU time, exchanges, the frames answered ahead (PIO_AHEAD), the reads
    and counts the firmware printed against the plant's edges."""
    with tempfile.TemporaryDirectory(prefix="mpy-fil-bench-") as tmp:
        main_dir = Path(tmp) / "fw"
        main_dir.mkdir()
        for name in ("main.py", "decoder.py"):
            (main_dir / name).write_bytes((PIO_BOT / name).read_bytes())
        (main_dir / "config.py").write_text(f"RUN_MS = {run_ms}\nREAD_MS = {read_ms}\n")
        more = {"watchdog_s": watchdog_s} if watchdog_s else {}  # (longer under valgrind: host/bench/icount.py)
        spec = RigSpec(str(PIO_BOT / "rig.toml"), seed=seed, main_dir=main_dir, allow_exit=True, **more)
        with Rig(spec, Recording(**recording)) as rig:
            rig.run_for(0.2)  # (start-up, the wheels at speed)
            fw0, cpu0, t0 = _fw_cpu_s(rig), time.process_time(), time.perf_counter()
            sim0, trips0, bus0, edges0 = (
                rig.t_us,
                rig.stats.link_round_trips,
                rig.stats.bus_round_trips,
                _plant_edges(rig),
            )
            local0 = rig.wiring.pio.ahead.local
            rig.run_for(run_ms / 1000 - 0.25)
            fw1, cpu1, wall = _fw_cpu_s(rig), time.process_time(), time.perf_counter() - t0
            result = {
                "sim_s": (rig.t_us - sim0) / 1e6,
                "wall_s": wall,
                "host_cpu_s": cpu1 - cpu0,
                "firmware_cpu_s": fw1 - fw0,
                "state_exchanges": rig.stats.link_round_trips - trips0,
                "pio_exchanges": rig.stats.bus_round_trips - bus0,
                "answered_ahead": rig.wiring.pio.ahead.local - local0,
                "edges_per_s": (_plant_edges(rig) - edges0) / ((rig.t_us - sim0) / 1e6),
            }
            rig.run_for(0.4)  # (stopped, counted, printed)
            truth = rig.truth()
            lines = [line.split()[1:] for line in rig.console.splitlines() if line.startswith("pio_bot ")]
            result["reads"], *counts = (int(v) for v in lines[-1]) if lines else (None, None, None)
            result["counts"] = tuple(counts)
            result["edges"] = (truth["enc_l_edges"], truth["enc_r_edges"])
    result["exchanges"] = result["state_exchanges"] + result["pio_exchanges"]
    return result


def pio_floor(run: dict, raw_us: float) -> tuple[float, str]:
    """The PIO decoder robot's floor: its exchanges a simulated second at the raw round trip
    (the read's own compute left out: the floor is, if anything, too high)."""
    per_s = run["exchanges"] / run["sim_s"]
    floor = floor_rtf(per_s, raw_us)
    return floor, (
        f"floor: {floor:.0f}x real time = 1 s / ({per_s:.0f} exchanges x raw {raw_us:.0f} us) a simulated s; "
        f"reached {run['sim_s'] / run['wall_s'] / floor:.0%} (target >= {PIO_FLOOR_SHARE:.0%})"
    )


def report_pio(run: dict, raw_us: float) -> None:
    sim_s = run["sim_s"]
    same = "counts = plant's edges" if run["counts"] == run["edges"] else f"COUNTS {run['counts']} != {run['edges']}"
    print(
        f"  {sim_s / run['wall_s']:.1f}x real time ({sim_s:.2f} simulated s in {run['wall_s']:.2f} wall s; CPU host "
        f"{run['host_cpu_s']:.2f} s, firmware {run['firmware_cpu_s']:.2f} s); {run['edges_per_s']:,.0f} edges/s; "
        f"{run['exchanges'] / sim_s:.0f} link exchanges a simulated s ({run['pio_exchanges'] / sim_s:.0f} a PIO "
        f"frame's own, {run['answered_ahead'] / sim_s:.0f} frames answered ahead: {pio_ahead.ENV}); "
        f"{run['reads']} reads; {same}"
    )
    print(f"    {pio_floor(run, raw_us)[1]}")


def kit_demo_folder(folder: Path, kit: str, parts, button, driver) -> Path:
    """The kit's rig file and its demo in ``folder``; the rig file's path."""
    import ast
    import shutil

    kit_dir = REPO / "host" / "kits" / kit
    text = (kit_dir / "rig.toml").read_text()
    if button:
        text = text.replace(f'name = "{button}"\n', f'name = "{button}"\npresses = [[0.2, 0.3]]\n')
    (folder / "rig.toml").write_text(text)
    for source, where in parts:
        shutil.copytree(HIL_FIRMWARE / source, folder / where, dirs_exist_ok=True)
    if driver:
        for module in driver_folder(driver).glob("*.py"):
            shutil.copy(module, folder)
    if not parts:  # (the written test's FIRMWARE, read without importing the test)
        tree = ast.parse((kit_dir / "test.py").read_text())
        found = [n.value.value for n in tree.body if isinstance(n, ast.Assign) and n.targets[0].id == "FIRMWARE"]
        (folder / "main.py").write_text(found[0])
    return folder / "rig.toml"


def run_kit_demo(kit: str, parts, button, driver, last: str, sim_s: float = KIT_SIM_S, **recording) -> dict:
    """A kit's demo on its rig until it ends (or ``sim_s``): wall and CPU time from the
    interpreter's start on, the link exchanges, how far it got, what it printed."""
    with tempfile.TemporaryDirectory(prefix="mpy-fil-bench-") as tmp:
        rig_file = kit_demo_folder(Path(tmp), kit, parts, button, driver)
        spec = RigSpec(str(rig_file), seed=1, allow_exit=True)
        with Rig(spec, Recording(**recording)) as rig, FirmwareCpu(rig) as firmware_cpu:
            fw_cpu0, cpu0, t0 = firmware_cpu(), time.process_time(), time.perf_counter()
            fw_cpu = [math.nan]

            def ended() -> bool:
                used = firmware_cpu() - fw_cpu0  # (the interpreter's, read while it runs: once it has
                if used >= 0:  # ended, /proc has it no more, or its sandbox's in its place)
                    fw_cpu[0] = used if math.isnan(fw_cpu[0]) else max(fw_cpu[0], used)
                return last in rig.console

            try:
                rig.run_until(ended, timeout_s=sim_s)
            except ExpectTimeout:
                pass  # (not ended within sim_s: its speed so far)
            wall, cpu = time.perf_counter() - t0, time.process_time() - cpu0
            return {
                "sim_s": rig.t_us / 1e6,
                "wall_s": wall,
                "host_cpu_s": cpu,
                "firmware_cpu_s": fw_cpu[0],
                "exchanges": rig.stats.link_round_trips + rig.stats.bus_round_trips,
                "bus_exchanges": rig.stats.bus_round_trips,
                "ended": last in rig.console,
                "console": rig.console,
                "bus_local": rig.stats.bus_local,
                "pio_local": rig.wiring.pio.ahead.local,
            }


def bench_kits() -> list:
    out = []
    for kit, *demo in KIT_DEMOS:
        try:
            out.append((kit, run_kit_demo(kit, *demo)))
        except DriverMissing as e:
            out.append((kit, {"missing": str(e)}))
    return out


def kit_floor(r: dict, raw_us: float) -> tuple[float, float]:
    """A kit's demo's floors: its link exchanges a simulated second at the raw round trip
    (what the link alone allows), and with its interpreter's own CPU a simulated second on
    top (what a host that cost nothing would reach: the firmware and the shim as they are)."""
    per_s = r["exchanges"] / r["sim_s"]
    interpreter_us = r["firmware_cpu_s"] * 1e6 / r["sim_s"]
    return floor_rtf(per_s, raw_us), floor_rtf(per_s, raw_us, 0.0 if math.isnan(interpreter_us) else interpreter_us)


def report_kits(kits: list, raw_us: float | None = None) -> None:
    for kit, r in kits:
        if "missing" in r:
            print(f"  {kit}: not run: {r['missing']}")
            continue
        factor, per_s = r["sim_s"] / r["wall_s"], 1000 / r["sim_s"]
        print(
            f"  {kit}: {r['sim_s']:.2f} simulated s{'' if r['ended'] else ' (not ended)'} in {r['wall_s']:.2f} s: "
            f"{factor:.1f}x real time (target {KIT_TARGET:g}x{'' if factor >= KIT_TARGET else ': below it'}); "
            f"{r['exchanges'] / r['sim_s']:.0f} link exchanges a simulated s "
            f"({r.get('bus_exchanges', 0) / r['sim_s']:.0f} of them bus transfers); CPU a simulated s: host "
            f"{r['host_cpu_s'] * per_s:.0f} ms, interpreter {r['firmware_cpu_s'] * per_s:.0f} ms"
        )
        if raw_us is not None:
            link, host_free = kit_floor(r, raw_us)
            print(
                f"    {floor_text(link, KIT_TARGET)} = 1 s / ({r['exchanges'] / r['sim_s']:.0f} exchanges x raw "
                f"{raw_us:.0f} us) a simulated s; reached {factor / link:.0%}; with the interpreter's own CPU, "
                f"a host that cost nothing: {host_free:.0f}x"
            )


def firmware_cpu_s(rig) -> float:
    """The interpreter's CPU time so far (user and system, from /proc; NaN where there is none)."""
    try:
        fields = Path(f"/proc/{sandbox.interpreter_pid(rig.target.proc)}/stat").read_text().rsplit(")", 1)[1].split()
    except (OSError, AttributeError, IndexError):
        return math.nan
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


class FirmwareCpu:
    """:func:`firmware_cpu_s` for a check every 10 simulated ms: the interpreter's pid found
    once and its ``stat`` kept open (a lookup of the sandbox's child and an open of /proc at
    each call took some 250 µs, a tenth of a kit demo's host CPU)."""

    def __init__(self, rig):
        try:
            self.fd = os.open(f"/proc/{sandbox.interpreter_pid(rig.target.proc)}/stat", os.O_RDONLY)
        except (OSError, AttributeError):
            self.fd = None

    def __call__(self) -> float:
        try:
            fields = os.pread(self.fd, 1024, 0).rsplit(b")", 1)[1].split()
        except (OSError, TypeError, IndexError):
            return math.nan
        return (int(fields[11]) + int(fields[12])) / CLOCK_TICKS

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        if self.fd is not None:
            os.close(self.fd)
            self.fd = None


CLOCK_TICKS = os.sysconf("SC_CLK_TCK")
BARE_IMU = """
import sys, time
class I2C:
    def __init__(self): self.mem = {(0x6A, 0x0F): 0x6C, (0x29, 0xC0): 0xEE, (0x6A, 0x1E): 0x03, (0x29, 0x13): 0x07}
    def readfrom_mem(self, addr, reg, n): return bytes((self.mem.get((addr, reg), 0),)) * n
    def readfrom_mem_into(self, addr, reg, buf):
        v = self.mem.get((addr, reg), 0x10)
        for i in range(len(buf)): buf[i] = v
    def writeto_mem(self, addr, reg, buf): pass
sys.path.insert(0, %r)
from lsm6dsox import LSM6DSOX
from vl53l0x import VL53L0X
i2c = I2C()
imu, tof = LSM6DSOX(i2c), VL53L0X(i2c)
heading = 0.0
def tick():
    global heading
    if imu.data_ready():
        gx, gy, gz, ax, ay, az = imu.read_raw()
        heading += gz * imu.gyro_scale / 208
def poll():
    if tof.ready():
        return tof.read_mm()
def best(call, n):
    t = []
    for _ in range(5):
        t0 = time.ticks_us()
        for i in range(n): call()
        t.append(time.ticks_diff(time.ticks_us(), t0))
    return min(t) / n
print(best(tick, %d), best(poll, %d))
"""


def bare_imu_us(n: int = 20_000) -> tuple[float, float]:
    """The bus-heavy robot's driver code in a bare MicroPython loop against a stub bus that
    answers at once (no shim, no link): wall us of a Timer tick (a data-ready poll and a
    12-byte read) and of a ranger's poll (its status, the range, the clear); the best of 5."""
    out = _bare(BARE_IMU % (str(IMU_BOT), n, n))
    tick_us, poll_us = (float(v) for v in out.split()[:2])
    return tick_us, poll_us


def bench_imu(run_ms: int = 10_000) -> dict:
    return {"run": run_imu_bot(run_ms), "bare": bare_imu_us()}


def imu_floor(run: dict, raw_us: float, bare: tuple[float, float]) -> tuple[float, str]:
    """The bus-heavy robot's floor: its exchanges a simulated second at the raw round trip,
    plus its driver code's bare cost (a Timer tick at 208 Hz, a ranger poll at 200 Hz)."""
    per_s = run["exchanges"] / run["sim_s"]
    compute_per_s = 208 * bare[0] + 200 * bare[1]
    floor = floor_rtf(per_s, raw_us, compute_per_s)
    return floor, (
        f"{floor_text(floor, IMU_TARGET)} = 1 s / ({per_s:.0f} exchanges x raw {raw_us:.0f} us + driver code "
        f"{compute_per_s / 1000:.2f} ms) a simulated s; reached {run['sim_s'] / run['wall_s'] / floor:.0%}"
    )


def report_imu(imu: dict, raw_us: float) -> None:
    run, bare = imu["run"], imu["bare"]
    sim_s = run["sim_s"]
    print(
        f"  {sim_s / run['wall_s']:.1f}x real time (target >= {IMU_TARGET:g}x) ({sim_s:.1f} simulated s in "
        f"{run['wall_s']:.2f} wall s; CPU host {run['host_cpu_s']:.2f} s, firmware {run['firmware_cpu_s']:.2f} s); "
        f"{run['transfers'] / sim_s:.0f} bus transfers and {run['exchanges'] / sim_s:.0f} link exchanges per "
        f"simulated s ({run['bus_exchanges'] / sim_s:.0f} of them a transfer's own, {run['bus_local'] / sim_s:.0f} "
        f"reads answered in the board; bus images {'on' if busimage.wanted() else 'off'}: {busimage.ENV})"
    )
    print(f"    {imu_floor(run, raw_us, bare)[1]}")
    print(f"  bare driver code (the limit): {bare[0]:.1f} us a Timer tick, {bare[1]:.1f} us a ranger poll")
    print(f"  firmware's summary: {run['printed']}")


def ratio(value_us: float, raw_us: float) -> str:
    return f"{value_us / raw_us:.2f}x raw"


def report_rover(rover: dict, raw_us: float) -> None:
    per_step_us = rover["wall_s"] * 1e6 / rover["control"]["count"]
    compute_us = rover["compute"]["p50"]
    limit = STEP_US / (raw_us + compute_us)
    print(
        f"  lockstep real-time factor: {rover['rtf']:.0f}x  ({rover['sim_s']:.0f} simulated s in "
        f"{rover['wall_s']:.2f} wall s; target >= 400x); limit 50 ms / (raw {raw_us:.0f} us + firmware compute "
        f"p50 {compute_us:.0f} us) = {limit:.0f}x, reached {rover['rtf'] / limit:.0%}"
    )
    print(f"  {lockstep_floor_line(rover, raw_us, ROVER_TARGET)}")
    print(f"  wall time per control step: {per_step_us:.0f} us ({ratio(per_step_us, raw_us)})")
    print(
        f"  link exchanges: {rover['round_trips']} ({rover['round_trips'] / rover['sim_s']:.0f} per simulated s); "
        f"control steps {rover['control']['count']}, misses {rover['control']['misses']}"
    )
    wake = rover["wake_rtt"]
    p50 = percentile(wake, 50)
    print(
        f"  per-wake round trip incl. firmware work: p50 {p50:.0f} us ({ratio(p50, raw_us)}), "
        f"p99 {percentile(wake, 99):.0f} us; host share outside it {per_step_us - p50:.0f} us per step"
    )


def lockstep_floor_line(run: dict, raw_us: float, target: float) -> str:
    """A lockstep run's floor: its exchanges a simulated second at the raw round trip, plus
    the firmware's compute a simulated second (every wake's ``control.compute``)."""
    per_s = run["round_trips"] / run["sim_s"]
    compute_per_s = run["compute_total_us"] / run["sim_s"]
    floor = floor_rtf(per_s, raw_us, compute_per_s)
    return (
        f"{floor_text(floor, target)} = 1 s / ({per_s:.0f} exchanges x raw {raw_us:.0f} us + firmware compute "
        f"{compute_per_s / 1000:.1f} ms) a simulated s; reached {run['sim_s'] / run['wall_s'] / floor:.0%}"
    )


PLANT_SHARE_ROBOTS = ("rover", "pool_cleaner")
"""The robots whose plant's own share of the host's exchange ``make bench`` prints."""


@functools.cache
def plant_share():
    """host/bench/plant_share.py (a script of that folder) as a module, loaded once."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("plant_share", REPO / "host" / "bench" / "plant_share.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def report_plant_shares(shares: list) -> None:
    """What the host's exchange is made of, against what issue 45's 65 % of the floor leaves it
    (docs/bench.md, "What the floors leave the host")."""
    lines = plant_share().lines
    for m in shares:
        print(f"  {m['robot']}, {m['sim_s']:g} simulated s, busy polling off: " + "; ".join(lines(m, 0.65)))


def report_duct(duct: dict, raw_us: float) -> None:
    per_exchange_us = duct["wall_s"] * 1e6 / duct["round_trips"]
    p50 = percentile(duct["state_wait"], 50)
    print(
        f"duct robot, single right branch (seed 3): {duct['sim_s'] / duct['wall_s']:.0f}x real time "
        f"({duct['sim_s']:.0f} simulated s in {duct['wall_s']:.1f} wall s); {duct['round_trips'] / duct['sim_s']:.0f} "
        f"exchanges per simulated s, {per_exchange_us:.0f} us each ({ratio(per_exchange_us, raw_us)}); STATE -> WAIT "
        f"p50 {p50:.0f} us; host share {per_exchange_us - statistics.fmean(duct['state_wait']):.0f} us an exchange"
    )


def report_pool(pool: dict, raw_us: float, plain: dict | None = None) -> None:
    per_exchange_us = pool["wall_s"] * 1e6 / pool["round_trips"]
    print(
        f"  full mission real-time factor: {pool['rtf']:.0f}x  ({pool['sim_s'] / 60:.1f} simulated min in "
        f"{pool['wall_s']:.1f} wall s; target >= 400x){'' if pool['done'] else ' -- NOT DONE'}"
    )
    if plain is None:
        print(f"  {lockstep_floor_line(pool, raw_us, POOL_TARGET)}")
    print(
        f"  link exchanges: {pool['round_trips']} ({pool['round_trips'] / pool['sim_s']:.0f} per simulated s), "
        f"{per_exchange_us:.0f} us each ({ratio(per_exchange_us, raw_us)}); pool floor cleaned {pool['coverage']:.1%}"
    )
    if plain is not None:
        print(
            f"  recorded (trace folder + link log, as make hil): {pool['wall_s'] / plain['wall_s'] - 1:+.0%} wall time "
            f"over unrecorded (target <= +30%; folder at stop: {pool['wall_s'] - pool['run_wall_s']:.1f} s), "
            f"peak memory {pool['peak_rss_mb']:.0f} MB (target < 150 MB), {pool['disk_mb']:.0f} MB on disk"
        )


def _run_only(args) -> bool:
    """One case alone (``--only-imu``, ``--only-pio``, ...): run and reported; False: none asked."""
    if args.only_imu:
        print("bus-heavy robot (host/bench/imu_bot): 10 simulated s")
        imu = bench_imu()
        raw = bench_raw()
        print(f"  raw pty round trip p50 {statistics.median(raw):.1f} us (after the run)")
        report_imu(imu, statistics.median(raw))
        return True
    if args.only_pio:
        print(PIO_TITLE)
        pio = run_pio_bot()
        raw = bench_raw()
        print(f"  raw pty round trip p50 {statistics.median(raw):.1f} us (after the run)")
        report_pio(pio, statistics.median(raw))
        return True
    if args.only_boards:  # (with the rover for a minute, the figure it is held to in the same run)
        print("two boards on one clock (docs/multi-board.md): 10 simulated s, beside the rover's 60")
        rover = bench_rover(60.0)
        per_s = {k: rover[k] / rover["sim_s"] for k in ("round_trips", "host_cpu_s", "fw_cpu_s")}
        print(
            f"  rover: {rover['rtf']:.0f}x real time ({per_s['round_trips']:.0f} link exchanges a simulated s; CPU a "
            f"simulated s: host {per_s['host_cpu_s'] * 1e3:.1f} ms, its interpreter {per_s['fw_cpu_s'] * 1e3:.1f} ms)"
        )
        report_boards(bench_boards(), rover)
        return True
    if args.only_kits:
        print(f"robot kits (host/kits): each kit's demo until it ends, at most {KIT_SIM_S:g} simulated s")
        kits = bench_kits()
        raw = bench_raw()
        print(f"  raw pty round trip p50 {statistics.median(raw):.1f} us (after the runs)")
        report_kits(kits, statistics.median(raw))
        return True
    if args.only_encoders:
        print("encoder-heavy robot (host/bench/encoder_bot): 10 simulated s at each rate")
        encoders = bench_encoders(per_edge=args.per_edge_encoders)
        raw = bench_raw()
        print(f"  raw pty round trip p50 {statistics.median(raw):.1f} us (after the runs)")
        report_encoders(encoders, statistics.median(raw))
        return True
    return False


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m host.bench", description=__doc__.split("\n")[0])
    parser.add_argument("--sim-minutes", type=float, default=10.0, help="simulated minutes of the rover (default 10)")
    parser.add_argument("--no-pool", action="store_true", help="skip the pool cleaner's full mission")
    parser.add_argument("--no-recorded", action="store_true", help="skip the recorded pool cleaner mission")
    parser.add_argument("--no-campaign", action="store_true", help="skip the campaign throughput (1 and 2 workers)")
    parser.add_argument("--no-encoders", action="store_true", help="skip the encoder-heavy robot")
    parser.add_argument("--only-encoders", action="store_true", help="the encoder-heavy robot only")
    parser.add_argument(
        "--per-edge-encoders",
        action="store_true",
        help="also the encoder-heavy robot with a STATE change an edge (its edges as segments otherwise)",
    )
    parser.add_argument("--no-imu", action="store_true", help="skip the bus-heavy robot")
    parser.add_argument("--only-imu", action="store_true", help="the bus-heavy robot only")
    parser.add_argument("--no-pio", action="store_true", help="skip the PIO decoder robot")
    parser.add_argument("--only-pio", action="store_true", help="the PIO decoder robot only")
    parser.add_argument("--no-kits", action="store_true", help="skip the robot kits' demos")
    parser.add_argument("--only-kits", action="store_true", help="the robot kits' demos only")
    parser.add_argument("--no-boards", action="store_true", help="skip the two boards on one clock")
    parser.add_argument(
        "--only-boards", action="store_true", help="the two boards on one clock only (and the rover a minute)"
    )
    parser.add_argument("--recorded-pool-child", metavar="DIR", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.recorded_pool_child:
        return _recorded_pool_child(args.recorded_pool_child)
    if _run_only(args):
        return 0
    print(f"raw pty round trip, CPython <-> MicroPython: {STATE_BYTES} bytes out, {REPLY_BYTES} back")
    raw_before = bench_raw()
    print(f"  p50 {statistics.median(raw_before):.1f} us, p99 {percentile(raw_before, 99):.0f} us")
    print(f"core loop benchmark: rover firmware, {args.sim_minutes:g} simulated minutes, 50 ms control quanta")
    rover = bench_rover(args.sim_minutes * 60)
    ping, ping_taken = bench_ping(2.0)
    duct = bench_duct()
    encoders = None if args.no_encoders else bench_encoders(per_edge=args.per_edge_encoders)
    imu = None if args.no_imu else bench_imu()
    pio = None if args.no_pio else run_pio_bot()
    kits = None if args.no_kits else bench_kits()
    two = None if args.no_boards else bench_boards()
    shares = [plant_share().measure(robot, 60.0, 3, statistics.median(raw_before)) for robot in PLANT_SHARE_ROBOTS]
    pool = plain = None
    if not args.no_pool:
        print("pool cleaner, full mission: 25 x 8 m pool, NMEA sonar byte by byte, 50 ms control quanta")
        plain = bench_pool()
        if not args.no_recorded:
            pool = bench_pool_recorded()
    raw_after = bench_raw()
    raw_us = statistics.median(raw_before + raw_after)
    print(
        f"raw pty round trip again: p50 {statistics.median(raw_after):.1f} us; "
        f"the ratios below are to the p50 of both, {raw_us:.1f} us"
    )
    report_rover(rover, raw_us)
    report_plant_shares(shares)
    p50 = percentile(ping, 50)
    print(
        f"  link round trip (STATE -> WAIT, pin-toggling firmware, {len(ping)} exchanges): p50 {p50:.0f} us "
        f"({ratio(p50, raw_us)}; target <= {STATE_WAIT_TARGET:g}x), p99 {percentile(ping, 99):.0f} us, "
        f"mean {statistics.fmean(ping):.0f} us"
    )
    taken = percentile(ping_taken, 50)
    print(
        f"    (to the read that brought the WAIT's bytes; to the WAIT taken, the OUT before it handled by the host: "
        f"p50 {taken:.0f} us, {ratio(taken, raw_us)})"
    )
    print(f"  {ratio_floor_text(1.0, STATE_WAIT_TARGET)}: the raw round trip itself, the same bytes each way")
    report_duct(duct, raw_us)
    if encoders is not None:
        print("encoder-heavy robot (host/bench/encoder_bot: Pin.irq on A and B of two wheels, a Timer PID):")
        report_encoders(encoders, raw_us)
    if imu is not None:
        print("bus-heavy robot (host/bench/imu_bot: an LSM6DSOX from a 208 Hz Timer, a VL53L0X polled, on I2C):")
        report_imu(imu, raw_us)
    if pio is not None:
        print(PIO_TITLE)
        report_pio(pio, raw_us)
    if kits is not None:
        print(f"robot kits (host/kits): each kit's demo until it ends, at most {KIT_SIM_S:g} simulated s:")
        report_kits(kits, raw_us)
    if two is not None:
        print("two boards on one clock (docs/multi-board.md):")
        report_boards(two, rover)
    if plain is not None:
        print("pool cleaner, full mission, unrecorded:")
        report_pool(plain, raw_us)
    if pool is not None:
        print("pool cleaner, full mission, recorded:")
        report_pool(pool, raw_us, plain)
    if not args.no_campaign:
        report_campaign()
    return 0


def report_campaign() -> None:
    one, lone, two = bench_campaign(1), bench_campaign(1, busy_poll=False), bench_campaign(2)
    print(
        f"campaign throughput ({one['runs']} rover runs of 300 simulated s; load average {os.getloadavg()[0]:.1f} "
        f"on {os.cpu_count()} cores): 1 worker {one['per_min']:.1f} runs/min ({lone['per_min']:.1f} without "
        f"busy polling), 2 workers {two['per_min']:.1f} runs/min: {two['per_min'] / one['per_min']:.2f}x "
        f"({two['per_min'] / lone['per_min']:.2f}x; target >= 1.7x); CPU per run {one['cpu_s']:.2f} s, "
        f"{lone['cpu_s']:.2f} s, {two['cpu_s']:.2f} s"
    )


def bench_ping(sim_s: float) -> tuple[list[float], list[float]]:
    """STATE -> WAIT of the pin-toggling firmware: to the read that brought the WAIT's bytes,
    and to the WAIT taken (the OUT before it handled by the host first)."""
    spec = RigSpec("rover", seed=0, main_dir=PING, busy_poll=busy_poll_wanted())
    with Rig(spec, Recording(time_round_trips=True)) as rig:
        rig.run_for(sim_s)
        return rig.stats.round_trip_us[10:], rig.stats.round_trip_taken_us[10:]


def bench_campaign(workers: int, runs: int = 16, sim_s: float = 300.0, busy_poll: bool = True) -> dict:
    """A campaign of ``runs`` rover runs of ``sim_s`` simulated seconds on ``workers`` local
    processes: its wall time from the pool's start to the last result (docs/campaigns.md).
    ``busy_poll`` False: a lone worker does not busy-poll its spare core either."""
    from host.campaign import load_campaign
    from host.campaign.runner import run_campaign

    campaign = load_campaign("rover", seeds=runs, seconds=sim_s, step_s=10.0)
    with tempfile.TemporaryDirectory(prefix="mpy-fil-bench-") as out:
        t0 = time.perf_counter()
        results = run_campaign(campaign, out, workers=workers, busy_poll=busy_poll)
        wall = time.perf_counter() - t0
    return {
        "runs": len(results),
        "passed": sum(r["passed"] for r in results),
        "wall_s": wall,
        "per_min": len(results) / wall * 60,
        "cpu_s": statistics.median(r.get("cpu_s", math.nan) for r in results),
    }


if __name__ == "__main__":
    raise SystemExit(main())
