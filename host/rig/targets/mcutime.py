"""The board's own time (docs/mcu-time.md): what the firmware executes, counted by the
harness's interpreter (host/core/micropython/hilcount.patch), costs what it costs on the
board's CPU. ``[board] cpu`` names the model; the shim charges the cost to virtual time at
the firmware's next clock read, wait or output (host/shim/_hil.py, ``_Cpu``).

A cost per kind of counted work, in CPU cycles: each bytecode by its class (:data:`CLASS`
of each opcode byte, py/bc0.h), a call into a C function, a heap allocation and its bytes,
a collection with the heap in use and the heap's size. The figures are fitted to published
board times (:data:`PUBLISHED`, docs/mcu-time.md): ``python -m host.mcubench`` runs the
kernels on the counting interpreter and prints the published time beside the charged one.
"""

import json
import struct
import subprocess
from dataclasses import dataclass, replace
from pathlib import Path

FREE = "free"


def _opcode_classes() -> list[str]:
    """Each opcode byte's class (py/bc0.h: the bases and the multi-opcode ranges)."""
    cls = ["other"] * 256
    simple = [0x50, 0x51, 0x52, 0x53, 0x22, 0x23, 0x24, 0x25, 0x26, 0x27, 0x10, 0x28, 0x29]
    simple += [0x57, 0x58, 0x59, 0x5A, 0x5B]  # dup, dup two, pop, rot two, rot three
    simple += [0x40, 0x42, 0x43, 0x44, 0x45, 0x46]  # jumps
    for b in simple:
        cls[b] = "simple"
    for b in range(0x70, 0xD0):  # small ints, LOAD_FAST_MULTI, STORE_FAST_MULTI
        cls[b] = "simple"
    for b in (0x11, 0x12, 0x13, 0x14, 0x15, 0x16, 0x17, 0x18, 0x19, 0x1A, 0x1B, 0x1C, 0x54):
        cls[b] = "lookup"  # names, globals, attributes, methods, imports, build_class
    for b in (0x55, 0x56):
        cls[b] = "subscr"
    for b in range(0xD0, 0x100):
        cls[b] = "op"  # unary and binary operators
    for b in (0x34, 0x35, 0x36, 0x37):
        cls[b] = "call"  # CALL_FUNCTION(_VAR_KW), CALL_METHOD(_VAR_KW): the frame and its return
    for b in (0x4B, 0x5E, 0x5F):
        cls[b] = "iter"  # FOR_ITER, GET_ITER, GET_ITER_STACK
    for b in (0x2A, 0x2B, 0x2C, 0x2D, 0x2E, 0x2F, 0x62, 0x30, 0x31, 0x32, 0x33, 0x20, 0x21):
        cls[b] = "build"  # tuples, lists, maps, sets, slices, comprehensions, unpacking, functions
    return cls


CLASS = _opcode_classes()
CLASSES = ("simple", "lookup", "subscr", "op", "call", "iter", "build", "other")
EXTRAS = ("ccall", "alloc", "alloc_byte", "collect", "gc_used_byte", "gc_total_byte")
COUNT_KEYS = ("ccalls", "allocs", "alloc_bytes", "collects", "gc_used_bytes", "gc_total_bytes")
CPU_FAMILIES = ("rp2040@125MHz", "esp32@240MHz", "esp32s3@240MHz", "rp2350@150MHz")
FAMILY_CPU = {
    "ESP32S3": "esp32s3@240MHz",  # (before ESP32: the first whose name the chip's starts with)
    "ESP32": "esp32@240MHz",
    "RP2350": "rp2350@150MHz",
    "RP2040": "rp2040@125MHz",
}
"""Each family's CPU, by the chip its board names (sys.implementation._machine's "with <chip>")."""
DEFAULT_ON = False
"""Whether a rig file without ``cpu`` gets its family's CPU (docs/mcu-time.md, "Default"):
not yet (17 app tests fail with it: figures pinned on a free CPU, and findings about the
apps' firmware, docs/mcu-time.md, "Our apps with MCU time on"); until then it gets "free"."""


BANNER_CHIPS = {"Pololu 3pi+ 2040 Robot": "RP2040"}
"""The chip of a board whose _machine names none (ports/rp2/boards/POLOLU_3PI_2040_ROBOT/
mpconfigboard.h: ``#define MICROPY_BANNER_MACHINE MICROPY_HW_BOARD_NAME``, 1.25 to 1.28)."""


def chip_of(machine: str) -> str:
    """The chip a board's ``sys.implementation._machine`` names ("... with RP2040"), or its
    :data:`BANNER_CHIPS` entry, else the whole name; upper-case."""
    return BANNER_CHIPS.get(machine, machine).rsplit(" with ", 1)[-1].upper()


def family_cpu(identity: tuple[str, str] | None) -> str:
    """The CPU of a board's family (:data:`FAMILY_CPU`, by the chip its identity names), or
    "free" when none is known."""
    if not identity:
        return FREE
    chip = chip_of(identity[1])
    return next((cpu for name, cpu in FAMILY_CPU.items() if chip.startswith(name)), FREE)


def default_cpu(identity: tuple[str, str] | None) -> str:
    """The cpu of a board whose rig file names none: its family's when :data:`DEFAULT_ON`."""
    return family_cpu(identity) if DEFAULT_ON else FREE


# Relative cost of each class of bytecode, in units of a simple one (a load, a store, a
# jump): shared by every CPU, which differ in a unit's cycles (fitted).
UNITS = {"simple": 1, "lookup": 4, "subscr": 3, "op": 2, "call": 10, "iter": 3, "build": 4, "other": 3}
POWER_OP = 0xF9  # MP_BC_BINARY_OP_MULTI + MP_BINARY_OP_POWER: a float power is a libm call

# The garbage collector's pause (py/gc.c: mark from the roots, then sweep the whole heap),
# in cycles: per byte of the board's heap (a sweep and the mark table: about 1.2 cycles a
# byte, from a full-heap scan of ~500 kB taking ~4 ms on an RP2350 at 150 MHz,
# micropython/micropython#15620, 2024-12) and per byte in use (marked: an estimate,
# docs/mcu-time.md), plus a fixed start (the roots: registers, the stack, the root pointers).
GC_FIXED = 20_000
GC_HEAP_BYTE = 1.2
GC_USED_BYTE = 12.0
ALLOC_BYTE = 1.0  # cycles per byte allocated (gc_alloc clears what it hands out)


@dataclass(frozen=True)
class Cpu:
    """A board CPU's cost model: its clock and the cycles of each counted kind."""

    name: str
    mhz: int
    unit: float  # cycles of a simple bytecode (UNITS scales the others)
    alloc: float  # a heap allocation (gc_alloc's search and the object's set-up)
    wide: float  # an int result past 31 bits (a big int on the board: allocated, mpz arithmetic)
    ccall: float  # a call into a C function (argument checks, the call, its result)
    power: float  # a float power (libm's pow)
    big_bit: float  # a bit of a big-int result (mpz arithmetic, linear in the size)
    heap: int  # the board's heap in bytes (MicroPython's gc.mem_free() + gc.mem_alloc() at start)

    def cycles(self) -> list[float]:
        """Cycles of each of the 256 opcode bytes, then of the counters' other kinds
        (:data:`EXTRAS`)."""
        ops = [self.unit * UNITS[CLASS[b]] for b in range(256)]
        ops[POWER_OP] = self.power
        collect = GC_FIXED + GC_HEAP_BYTE * self.heap
        return [*ops, self.ccall, self.alloc, ALLOC_BYTE, collect, GC_USED_BYTE, 0.0, self.wide, self.big_bit]

    def table(self) -> bytes:
        """The weights the shim gives _hilfast.cost: picoseconds of each kind, uint32 LE."""
        ps_per_cycle = 1e6 / self.mhz
        return struct.pack(
            "<%dI" % (256 + len(EXTRAS)), *(min(round(c * ps_per_cycle), 2**32 - 1) for c in self.cycles())
        )

    def charge_us(self, counts: dict, used_base: int = 0) -> float:
        """What ``counts`` (_hilfast.counts, or a difference of two) cost, in µs."""
        c = self.cycles()
        total = sum(n * c[b] for b, n in enumerate(counts["ops"]))
        for i, key in enumerate(COUNT_KEYS):
            n = counts.get(key, 0)
            if key == "gc_used_bytes":
                n = max(0, n - counts.get("collects", 0) * used_base)
            total += n * c[256 + i]
        return total / self.mhz


EXTRAS = (*EXTRAS, "wide", "big_bit")
COUNT_KEYS = (*COUNT_KEYS, "wide", "big_bits")

# -- the firmware's CPU load, for the report ------------------------------------------

WINDOW_US = 100_000  # (the shim's CPU_IRQ comes at most once a window: host/shim/_hilframe.py)
"""The CPU load's window: the busy share of each 100 ms of virtual time."""
LONGEST = 5
"""The longest compute stretches kept, each with the code that ran it."""


class CpuLoad:
    """The firmware's CPU load over a run with MCU time (the report's view, docs/mcu-time.md):
    each WAIT's compute (the main program's, charged since the wait before; it ran up to the
    wait's instant) spread over the windows it spans, and the longest stretches between two
    waits with the code that ran them (the shim's CPU messages, sent when a stretch is the
    longest so far: outermost frame first, the largest piece's)."""

    def __init__(self, cpu: str):
        self.cpu = cpu
        self.busy: dict[int, int] = {}  # window index -> µs of the main program's compute in it
        self.irq: dict[int, float] = {}  # window index -> µs of the callbacks' compute in it
        self.longest: list[dict] = []

    def wait(self, t_now: int, compute_us: int) -> None:
        t = t_now - compute_us
        if t < 0:
            t = 0
        busy = self.busy
        while t < t_now:
            w = t // WINDOW_US
            end = min(t_now, (w + 1) * WINDOW_US)
            busy[w] = busy.get(w, 0) + end - t
            t = end

    def callbacks(self, t_from: int, t_us: int, compute_us: int) -> None:
        """The callbacks' compute between two instants (a CPU_IRQ message), spread evenly over
        them (the shim tells it once a window, not at each handler)."""
        span = t_us - t_from
        if span <= 0:
            w = t_us // WINDOW_US
            self.irq[w] = self.irq.get(w, 0) + compute_us
            return
        t = t_from
        while t < t_us:
            w = t // WINDOW_US
            end = min(t_us, (w + 1) * WINDOW_US)
            self.irq[w] = self.irq.get(w, 0) + compute_us * (end - t) / span
            t = end

    def stretch(self, t_us: int, compute_us: int, piece_us: int, code: str) -> None:
        self.longest.append({"t_us": t_us, "compute_us": compute_us, "piece_us": piece_us, "code": code})
        self.longest.sort(key=lambda s: -s["compute_us"])
        del self.longest[LONGEST:]

    def shares(self, t_end_us: int, busy: dict | None = None) -> list[float]:
        """The busy share of each window up to ``t_end_us`` (the last one's, of its part
        run): the main program's, or with ``busy`` the callbacks' (which may pass 1: the
        board would fall behind)."""
        busy = self.busy if busy is None else busy
        out = []
        for w in range((t_end_us + WINDOW_US - 1) // WINDOW_US):
            span = min(WINDOW_US, t_end_us - w * WINDOW_US)
            out.append(round(busy.get(w, 0) / span, 4) if span > 0 else 0.0)
        return out

    def record(self, t_end_us: int) -> dict:
        """For the trace's header (``mcu_time``): the CPU, the window, each window's busy
        share (the main program's, the callbacks') and the longest stretches."""
        return {
            "cpu": self.cpu,
            "window_us": WINDOW_US,
            "busy_share": self.shares(t_end_us),
            "callbacks_share": self.shares(t_end_us, self.irq),
            "longest": self.longest,
        }


# -- calibration ----------------------------------------------------------------------

KERNELS = Path(__file__).resolve().parent.parent / "mcubench" / "kernels.py"
CALIBRATION_HEAP = "400K"  # the interpreter's heap for the kernels (64-bit objects: about twice a board's)

SOURCES = {
    "shaoziyang": "github.com/shaoziyang/micropython_benchmarks README.md (commit 48360b7, MicroPython v1.23.0, 2024)",
    "scruss": (
        "scruss.com/blog/tag/benchmark, 'Parallel MicroPython Benchmarking' results"
        " (MicroPython 1.24.1/1.25.0 preview, 2025)"
    ),
}
# Published board times in ms of the kernels (host/mcubench/kernels.py, written after the
# source's descriptions): 100,000 loop iterations, Mandelbrot at 100 and 500 iterations,
# pi to 1000 digits. (ESP32: measured at MicroPython's default 160 MHz.)
PUBLISHED = {
    "rp2040@125MHz": {
        "int_add": 799, "int_mul": 2823, "int_div": 1321, "float_add": 1343, "float_mul": 1343,
        "float_div": 1399, "float_pow": 9988, "mandelbrot_100": 5212, "mandelbrot_500": 18820, "pi_1000": 868,
    },
    "esp32@160MHz": {
        "int_add": 611, "int_mul": 1934, "int_div": 866, "float_add": 946, "float_mul": 937,
        "float_div": 981, "float_pow": 1391, "mandelbrot_100": 2977, "mandelbrot_500": 9931, "pi_1000": 660,
    },
    "esp32s3@240MHz": {
        "int_add": 338, "int_mul": 1099, "int_div": 488, "float_add": 526, "float_mul": 523,
        "float_div": 551, "float_pow": 801, "mandelbrot_100": 1565, "mandelbrot_500": 5448, "pi_1000": 389,
    },
}  # fmt: skip
RP2350_VS_RP2040 = 10.3 / 19.8  # scruss: the same benchmark on a Pico 2 W (RP2350 @ 150) and a Pico W (RP2040 @ 125)
HEAPS = {
    "rp2040": 233_024,
    "esp32": 166_592,
    "esp32s3": 244_224,
    "rp2350": 480_000,
}  # shaoziyang's Memory row; rp2350: #15620


def run_kernels(interpreter: str | None = None, heap: str = CALIBRATION_HEAP) -> dict[str, dict]:
    """Each kernel's counts on the counting interpreter (one run of host/mcubench/kernels.py)."""
    from host.core import interpreter as interp

    path = interpreter or str(interp.find())
    out = subprocess.run(
        [path, "-X", f"heapsize={heap}", str(KERNELS)], capture_output=True, text=True, timeout=300, check=True
    ).stdout
    return {d["name"]: d for d in map(json.loads, out.splitlines())}


def _features(cpu_heap: int, counts: dict) -> tuple[list[float], float]:
    """The fitted kinds' counts of a kernel ([unit, alloc, wide, ccall, power, big_bit]) and the
    cycles of the fixed kinds (bytes allocated, the collector)."""
    units = sum(n * UNITS[CLASS[b]] for b, n in enumerate(counts["ops"]) if b != POWER_OP)
    fixed = counts["alloc_bytes"] * ALLOC_BYTE + counts["collects"] * (GC_FIXED + GC_HEAP_BYTE * cpu_heap)
    fixed += GC_USED_BYTE * counts["gc_used_bytes"]
    return [
        units,
        counts["allocs"],
        counts["wide"],
        counts["ccalls"],
        counts["ops"][POWER_OP],
        counts["big_bits"],
    ], fixed


def fit(counts: dict[str, dict], published: dict[str, float], mhz: int, heap: int) -> list[float]:
    """Non-negative least squares of the relative errors: [unit, alloc, wide, ccall, power, big_bit]."""
    import numpy as np

    names = sorted(published)
    rows, ys = [], []
    for name in names:
        f, fixed = _features(heap, counts[name])
        y = published[name] * 1e-3 * mhz * 1e6
        rows.append([v / y for v in f])
        ys.append(1.0 - fixed / y)
    a, y = np.array(rows), np.array(ys)
    scale = np.linalg.norm(a, axis=0)
    scale[scale == 0] = 1
    b = a / scale
    x = np.zeros(b.shape[1])
    g, h = b.T @ b, b.T @ y
    for _ in range(5000):  # projected coordinate descent (six unknowns)
        for j in range(len(x)):
            if g[j, j]:
                x[j] = max(0.0, x[j] - (g[j] @ x - h[j]) / g[j, j])
    return list(x / scale)


def fitted(counts: dict[str, dict]) -> dict[str, Cpu]:
    """The four CPUs' models from the published figures (:func:`fit`); the ESP32's at
    240 MHz from its 160 MHz figures (the same cycles), the RP2350's from the RP2040's
    scaled by their published ratio."""
    cpus = {}
    for key, family, mhz in (
        ("rp2040@125MHz", "rp2040", 125),
        ("esp32@160MHz", "esp32", 160),
        ("esp32s3@240MHz", "esp32s3", 240),
    ):
        x = fit(counts, PUBLISHED[key], mhz, HEAPS[family])
        name = "esp32@240MHz" if family == "esp32" else key
        cpus[name] = Cpu(name, 240 if family == "esp32" else mhz, *(round(float(v), 1) for v in x), HEAPS[family])
    rp = cpus["rp2040@125MHz"]
    k = RP2350_VS_RP2040 * 150 / 125
    cpus["rp2350@150MHz"] = Cpu(
        "rp2350@150MHz",
        150,
        *(round(float(v * k), 1) for v in (rp.unit, rp.alloc, rp.wide, rp.ccall, rp.power, rp.big_bit)),
        HEAPS["rp2350"],
    )
    return cpus


# The models, as :func:`fitted` makes them from the kernels' counts (``python -m
# host.mcubench`` fits them again and prints the table of docs/mcu-time.md).
CPUS = {
    "rp2040@125MHz": Cpu("rp2040@125MHz", 125, 43.4, 637.3, 2530.7, 3057.8, 10883.3, 5.3, HEAPS["rp2040"]),
    "esp32@240MHz": Cpu("esp32@240MHz", 240, 42.4, 463.9, 2118.3, 1556.9, 823.7, 5.3, HEAPS["esp32"]),
    "esp32s3@240MHz": Cpu("esp32s3@240MHz", 240, 35.2, 384.3, 1827.4, 1139.3, 744.1, 4.7, HEAPS["esp32s3"]),
    "rp2350@150MHz": Cpu("rp2350@150MHz", 150, 27.1, 397.8, 1579.8, 1908.8, 6793.8, 3.3, HEAPS["rp2350"]),
}
assert tuple(CPUS) == CPU_FAMILIES


def check_cpu(value) -> str | None:
    """Why ``[board] cpu`` cannot be ``value``, or None."""
    if value == FREE or value in CPUS:
        return None
    return f"expected one of {', '.join((*CPUS, FREE))}, got {value!r}"


WORD_RATIO = 2
"""This build's objects to a board's: 64-bit words against 32-bit ones (a board's heap holds
what takes twice its bytes here)."""


def heap_model(cpu: str, heap_size: int | None = None) -> int:
    """The heap the firmware's collections are scheduled by (py/gc.c, ``mp_hil_heap_start``), in
    this build's bytes: the rig file's ``[interpreter] heap_size`` when it sets one (the
    firmware's heap as on its board), else the CPU's board's (:data:`HEAPS`) at this build's
    object size."""
    return heap_size or WORD_RATIO * CPUS[cpu].heap


def shim_settings(cpu: str, heap_size: int | None = None) -> dict:
    """What the shim is told of the cpu in WELCOME (host/rig/targets/firmware.py ShimSettings:
    ``cpu`` its name; ``cpu_cost`` the weights; ``cpu_heap`` the modelled heap,
    :func:`heap_model`, whose size a collection's sweep costs: the rig file's heap_size in a
    board's bytes when it names one). Nothing for a free CPU."""
    if cpu == FREE:
        return {}
    model = CPUS[cpu] if not heap_size else replace(CPUS[cpu], heap=heap_size // WORD_RATIO)
    return {"cpu": cpu, "cpu_cost": model.table(), "cpu_heap": heap_model(cpu, heap_size)}


def table(counts: dict[str, dict], cpus: dict[str, Cpu] | None = None) -> list[tuple]:
    """(cpu, kernel, published ms, charged ms, difference %) for each published figure."""
    cpus = cpus or CPUS
    rows = []
    for key, published in PUBLISHED.items():
        name = key.replace("@160MHz", "@240MHz")
        scale = 240 / 160 if name != key else 1.0  # (the same cycles at the published clock)
        for kernel in sorted(published):
            charged = cpus[name].charge_us(counts[kernel]) / 1000 * scale
            rows.append((key, kernel, published[kernel], round(charged), 100 * (charged / published[kernel] - 1)))
    return rows


def main(argv: list[str]) -> int:
    interpreter = argv[0] if argv else None
    counts = run_kernels(interpreter)
    fresh = fitted(counts)
    print("fitted now (CPUS holds these, rounded):")
    for cpu in fresh.values():
        print("  ", cpu)
    print("\n| CPU | kernel | published ms | charged ms | difference |\n|---|---|---|---|---|")
    for key, kernel, pub, charged, diff in table(counts):
        print(f"| {key} | {kernel} | {pub} | {charged} | {diff:+.1f} % |")
    return 0
