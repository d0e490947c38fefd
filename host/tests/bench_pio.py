"""What a PIO quadrature decoder costs (docs/shim.md, "PIO"): run with
``.venv/bin/python -m host.tests.bench_pio [seconds]``; it prints:

- the raw pty round trip, measured first;
- **emulator**: the host's PIO alone (sim_plant/pio) following an encoder at 10,000
  edges a second, a frame's changes at a time: instructions stepped and wall time per edge;
- **the wheel still**: the in-the-loop firmware below with its motor off, no edge at all:
  what its frames alone cost, a bound on the in-the-loop figures;
- **in the loop**: examples/pico_pio_bot's decoder on a robot whose left encoder gives
  10,000 edges a second, the firmware reading the count every 20 ms: virtual seconds per
  wall second, the host's and the interpreter's CPU time an edge, the frames a simulated
  second and what the link alone allows; and the same robot counted with ``Pin.irq`` (an
  edge is a change sent to the firmware) for comparison.
"""

import os
import re
import sys
import tempfile
import time
from pathlib import Path

from host.bench import bench_raw
from host.core.paths import REPO
from host.pytest_plugin import rig_from_keywords
from host.rig.targets.sandbox import interpreter_pid
from host.tests import pio_corpus
from sim_plant.pio import PioBlock, PioConfig

sys.path.insert(0, str(REPO / "host" / "shim"))
import _pioasm  # noqa: E402

EDGES_PER_S = 10_000
QUAD = [(0, 0), (1, 0), (1, 1), (0, 1)]


def emulator_only(seconds: float, edges_per_s: int = EDGES_PER_S, batch: int = 100) -> dict:
    body, settings, _text = pio_corpus.CORPUS["quadrature"]
    prog = _pioasm.asm_pio(**settings)(body)
    block = PioBlock()
    block.load(list(prog[0]))
    sm = block.init(0, PioConfig(prog[3], prog[4], 2 << 15, 256, 0), 0)  # 125 MHz, in_base GP2
    block.set_active(0, True, 0)
    n_edges = int(seconds * edges_per_s)
    gap_us = 1_000_000 // edges_per_s
    changes = []
    for i in range(1, n_edges + 1):
        a, b = QUAD[i % 4]
        changes.append((i * gap_us, 2 if a != QUAD[(i - 1) % 4][0] else 3, a if a != QUAD[(i - 1) % 4][0] else b))
    wall = time.perf_counter()
    for start in range(0, n_edges, batch):  # (as the host gives them: a frame's committed changes)
        window = changes[start : start + batch]
        block.advance(window[-1][0], window)
    block.advance((n_edges + 1) * gap_us)
    wall = time.perf_counter() - wall
    count = sm.x - (1 << 32) if sm.x & 0x80000000 else sm.x
    assert count == n_edges, (count, n_edges)
    return {
        "edges": n_edges,
        "steps_per_edge": block.steps / n_edges,
        "wall_us_per_edge": wall / n_edges * 1e6,
        "x_real_time": seconds / wall,
    }


FIRMWARE_PIO = """
import time
from machine import Pin, PWM
import rp2
from main_decoder import quadrature
sm = rp2.StateMachine(0, quadrature, in_base=IN_BASE)
sm.active(1)
def count():
    for _ in range(sm.rx_fifo()):
        sm.get()
    n = sm.get()
    return n - (1 << 32) if n & 0x80000000 else n
"""
FIRMWARE_IRQ = """
import time
from machine import Pin, PWM
a, b = Pin(2, Pin.IN), Pin(3, Pin.IN)
n = 0
def edge_a(p):
    global n
    n += 1 if a.value() != b.value() else -1
def edge_b(p):
    global n
    n += 1 if a.value() == b.value() else -1
a.irq(edge_a, Pin.IRQ_RISING | Pin.IRQ_FALLING)
b.irq(edge_b, Pin.IRQ_RISING | Pin.IRQ_FALLING)
def count():
    return n
"""
DRIVE = """
Pin(22, Pin.OUT, value=1)
Pin(17, Pin.OUT, value=1)
Pin(18, Pin.OUT, value=0)
motor = PWM(Pin(16), freq=20000, duty_u16=DUTY)
t_stop = time.ticks_add(time.ticks_ms(), RUN_MS)
while time.ticks_diff(t_stop, time.ticks_ms()) > 0:
    time.sleep_ms(20)
    count()
motor.duty_u16(0)
time.sleep_ms(50)
print("count", count())
while True:
    time.sleep_ms(100)
"""


def _rig_folder(folder: Path, firmware: str, lines_per_rev: int, run_ms: int, in_base: str, duty: int) -> Path:
    rig = (REPO / "examples" / "pico_pio_bot" / "rig.toml").read_text()
    rig = rig.replace("lines_per_rev = 7", f"lines_per_rev = {lines_per_rev}", 1)
    rig = rig.replace("room_w_m = 3.0\nroom_h_m = 2.0", "room_w_m = 40.0\nroom_h_m = 40.0")
    (folder / "rig.toml").write_text(rig)
    settings = f"DUTY = {duty}\nRUN_MS = {run_ms}\nIN_BASE = {in_base}\n"
    imports = "from machine import Pin, PWM\n"
    (folder / "main.py").write_text(firmware.replace(imports, imports + settings, 1) + DRIVE)
    main = (REPO / "examples" / "pico_pio_bot" / "main.py").read_text()
    decoder = main[main.index("@rp2.asm_pio") : main.index("class PioEncoder")]
    (folder / "main_decoder.py").write_text("# ruff: noqa\nimport rp2\n\n\n" + decoder)
    return folder / "rig.toml"


def _count_sent(inputs) -> list:
    """[the input changes the rig has sent the firmware so far] (counted as STATEs take them)."""
    sent, take = [0], inputs.take

    def counted():
        batch = take()
        sent[0] += len(batch)
        return batch

    inputs.take = counted
    return sent


def _count_frames(rig) -> list:
    """[the frames the shim has sent so far]."""
    frames, dispatch = [0], rig.dispatch

    def counted(type_, payload):
        frames[0] += 1
        return dispatch(type_, payload)

    rig.dispatch = counted
    return frames


def _cpu_s(pid: int) -> float:
    """A process's CPU time (user + system) from /proc."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def in_the_loop(
    seconds: float, firmware: str, in_base: str = "Pin(2)", lines_per_rev: int = 64, duty: int = 65535
) -> dict:
    """The robot driving ahead for ``seconds`` (after 0.2 s of start-up), then stopping: the
    wall time of the drive, the host's and the interpreter's CPU time, the frames the shim
    sent, the edges a second, the count read at the end."""
    with tempfile.TemporaryDirectory() as tmp:
        folder = _rig_folder(Path(tmp), firmware, lines_per_rev, round((seconds + 0.2) * 1000), in_base, duty)
        rig = rig_from_keywords(str(folder), seed=1, record=False)
        sent = _count_sent(rig.inputs)
        rig.start()
        frames = _count_frames(rig)
        try:
            rig.run_for(0.2)  # (start-up, and the wheel at speed)
            pid = interpreter_pid(rig.target.proc)
            edges0 = rig.truth()["enc_l_edges"]
            trips, sent0, frames0 = rig.stats.link_round_trips, sent[0], frames[0]
            cpu_fw, cpu_host = _cpu_s(pid), time.process_time()
            wall = time.perf_counter()
            rig.run_for(seconds)
            wall = time.perf_counter() - wall
            cpu_fw, cpu_host = _cpu_s(pid) - cpu_fw, time.process_time() - cpu_host
            trips, sent0, frames0 = rig.stats.link_round_trips - trips, sent[0] - sent0, frames[0] - frames0
            edges = rig.truth()["enc_l_edges"]
            rig.run_for(0.2)
            console = rig.console
            counts = re.findall(r"count (-?\d+)", console)
            final = rig.truth()["enc_l_edges"]
        finally:
            rig.stop()
    n = max(1, edges - edges0)
    return {
        "edges_per_s": (edges - edges0) / seconds,
        "x_real_time": seconds / wall,
        "host_cpu_us_per_edge": cpu_host / n * 1e6,
        "firmware_cpu_us_per_edge": cpu_fw / n * 1e6,
        "frames_per_s": frames0 / seconds,
        "round_trips": trips,
        "changes_sent": sent0,
        "last_count": int(counts[-1]) if counts else None,
        "console": console,
        "plant_edges": final,
    }


def main(argv: list[str]) -> None:
    seconds = float(argv[0]) if argv else 2.0
    raw = sorted(bench_raw(2000))
    raw_us = raw[len(raw) // 2]
    print(f"raw pty round trip, CPython <-> MicroPython: p50 {raw_us:.0f} us")
    emu = emulator_only(seconds)
    print(
        f"emulator: {emu['edges']} edges at {EDGES_PER_S}/s, {emu['steps_per_edge']:.1f} steps and "
        f"{emu['wall_us_per_edge']:.1f} us a edge: {emu['x_real_time']:.1f}x real time"
    )
    cases = (
        ("PIO decoder, in_base=Pin(2)", FIRMWARE_PIO, "Pin(2)"),
        ("PIO decoder, in_base=2", FIRMWARE_PIO, "2"),
        ("Pin.irq on A and B", FIRMWARE_IRQ, "None"),
    )
    still = in_the_loop(seconds, FIRMWARE_PIO, "2", duty=0)
    print(
        f"the same firmware with the wheel still (no edge at all): {still['x_real_time']:.1f}x real time, "
        f"{still['frames_per_s']:.0f} frames a simulated s: the frames' own cost, a bound on the cases below"
    )
    for name, firmware, in_base in cases:
        loop = in_the_loop(seconds, firmware, in_base)
        floor = 1e6 / (loop["frames_per_s"] * raw_us)
        print(
            f"in the loop, {name}: {loop['edges_per_s']:.0f} edges/s, {loop['x_real_time']:.1f}x real time "
            f"(target >= 50x); CPU an edge: host {loop['host_cpu_us_per_edge']:.1f} us, interpreter "
            f"{loop['firmware_cpu_us_per_edge']:.1f} us; {loop['frames_per_s']:.0f} frames a simulated s "
            f"({loop['round_trips']} round trips), {loop['changes_sent']} input changes sent; the link alone "
            f"(frames x raw round trip) allows {floor:.0f}x (the count read {loop['last_count']}, the plant's "
            f"edges {loop['plant_edges']})"
        )


if __name__ == "__main__":
    main(sys.argv[1:])
