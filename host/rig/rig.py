"""The rig: MicroPython + shim + firmware + plant, run in lockstep virtual time.

A :class:`Rig` starts the unix port with the shim first on ``MICROPYPATH`` and the
firmware's folders after it (as a board's filesystem has them), shakes hands over a
raw pty, and then serves the shim: actuator writes go to the plant at their virtual
time; a WAIT advances the plant to the time asked for, or to the first edge that fires
a registered IRQ, and answers with the inputs that changed and the *horizon* (the
earliest time an input may change next). ``docs/clock.md`` describes the protocol of
time; ``docs/protocol.md`` the bytes.

Every wait on the firmware has a wall-clock deadline (the watchdog); a firmware that
stops answering is stopped and reported, and :meth:`Rig.stop` always ends the
process and closes the pty.
"""

import copy
import inspect
import os
import signal
import struct
import subprocess
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from host.artefacts.folder import write_trace_folder
from host.artefacts.linklog import Trace
from host.artefacts.recorder import ACTUATOR, PIN, Recorder
from host.artefacts.recorder import PROBE as PROBE_ROLE
from host.core import interpreter
from host.core.errors import ConfigError, FirmwareError, FirmwareHung, LinkError, LinkTimeout
from host.core.paths import SHIM_DIR
from host.link import Channel, FdTransport, PtyPair, spare_core
from host.rig.apps import PROBE, App, get_app
from host.rig.boards import board_dir, pin_key, read_pin_map
from host.rig.budgets import ComputeBudget, LatencyBudget, PeriodBudget, PulseBudget
from host.shim import _hilframe as F

MODES = {"lockstep": F.MODE_LOCKSTEP, "realtime": F.MODE_REALTIME}
HANDSHAKE_TIMEOUT_S = 10.0
CONSOLE_TAIL_LINES = 20
MAX_BATCH = 200  # changes in one STATE (15 bytes each)
CHUNK_US = 20_000  # lockstep plant advance step inside a batch
MAX_BATCH_BYTES = 800  # UART bytes in one STATE
BUSY_POLL_S = 0.0005  # lockstep: read the link in a loop this long before sleeping
PROGRESS_EVERY_S = 0.25  # wall time between two progress reports
MSG_NAMES = {
    F.HELLO: "HELLO",
    F.CFG: "CFG",
    F.OUT: "OUT",
    F.WAIT: "WAIT",
    F.SEEN: "SEEN",
    F.UART_TX: "UART_TX",
    F.FAULT: "FAULT",
    F.EXIT: "EXIT",
}
CFG_KINDS = {F.CFG_PIN: "pin", F.CFG_ADC: "adc", F.CFG_PWM: "pwm", F.CFG_UART: "uart", F.CFG_IRQ: "irq"}
OUT_ATTRS = {F.OUT_LEVEL: "level", F.OUT_DUTY: "duty_u16", F.OUT_FREQ: "freq", F.OUT_DEINIT: "deinit"}


@dataclass
class Handle:
    """One shim object (pin, ADC, PWM, UART) and what it is wired to."""

    kind: int
    key: str  # pin id as the shim names it
    board_name: str | None
    signal: str | None  # plant signal or "probe:<name>"
    is_input: bool = False
    pull: int = 0
    irq: int = 0  # trigger mask
    samples: int = 0
    level: int | None = None  # last level driven on an output


_OUT = struct.Struct("<QHBi")
_WAIT = struct.Struct("<QQI")
_NO_WATCH = frozenset()


@dataclass
class _Wait:
    t_now: int
    t_until: int
    watch: frozenset


@dataclass
class RunStats:
    link_round_trips: int = 0
    irq_edges: int = 0
    rollbacks: int = 0
    lease_violations: int = 0
    round_trip_us: list = field(default_factory=list)


_IMMUTABLE = (int, float, str, bytes, bool, type(None), frozenset)


def _copy_state(value, gens: list):
    """A deep copy of plant state that is cheap for what plants hold (numbers, tuples of
    numbers, small lists and dicts, component objects); numpy Generators are kept by
    reference and their bit-generator state is saved in ``gens`` instead."""
    if isinstance(value, _IMMUTABLE):
        return value
    if isinstance(value, list):
        return [_copy_state(v, gens) for v in value]
    if isinstance(value, dict):
        return {k: _copy_state(v, gens) for k, v in value.items()}
    if isinstance(value, tuple):
        return value if all(isinstance(v, _IMMUTABLE) for v in value) else tuple(_copy_state(v, gens) for v in value)
    if isinstance(value, np.random.Generator):
        gens.append(value)
        return value
    if isinstance(value, np.ndarray):
        return value.copy()
    if hasattr(value, "__dict__") and not isinstance(value, type):
        clone = copy.copy(value)
        clone.__dict__.update(_copy_state(value.__dict__, gens))
        return clone
    return copy.deepcopy(value)


class Rig:
    """Firmware in the loop. Use as a context manager, or call start() and stop()."""

    REQUIRE_MAIN = True

    def __init__(
        self,
        app: str | App = "rover",
        *,
        board: str | None = None,
        seed: int = 0,
        mode: str = "lockstep",
        plant=None,
        plant_options: dict | None = None,
        main_dir: Path | None = None,
        firmware_dir: Path | None = None,
        watchdog_s: float = 5.0,
        artefacts: Path | None = None,
        trace: bool = False,
        record: bool = False,
        progress=None,
        time_round_trips: bool = False,
    ):
        """``trace`` writes the link messages to ``artefacts/trace.jsonl``; ``record``
        keeps every signal and ground truth and writes the trace folder at stop()
        (docs/traces.md); ``progress(t_us, t_end_us)`` is called while run_until()
        runs, at most every PROGRESS_EVERY_S of wall time and when it ends."""
        self.app = get_app(app) if isinstance(app, str) else app
        self.board = board or self.app.default_board
        if mode not in MODES:
            raise ConfigError(f"mode: expected one of {sorted(MODES)}, got {mode!r}")
        if watchdog_s <= 0:
            raise ConfigError(f"watchdog_s: expected a positive number of seconds, got {watchdog_s!r}")
        self.mode = mode
        self.seed = seed
        self.watchdog_s = watchdog_s
        self.board_path = board_dir(self.board)
        pins = read_pin_map(self.board)
        unknown = sorted(set(self.app.wiring) - set(pins))
        if unknown:
            raise ConfigError(f"wiring: board {self.board} has no pin named {', '.join(unknown)}")
        self.pin_names = {pin_key(n, v): n for n, v in pins.items() if n in self.app.wiring}
        if firmware_dir is not None:  # a flashed board folder: main.py, board.mpy, lib/
            self.main_dir = Path(firmware_dir)
            self.firmware_folders = [self.main_dir, self.main_dir / "lib"]
            if self.REQUIRE_MAIN and not (self.main_dir / "main.py").is_file():
                raise ConfigError(f"firmware_dir: no main.py in {self.main_dir} (flash it first: make flash)")
        else:
            self.main_dir = Path(main_dir) if main_dir else self.app.path
            if not (self.main_dir / "main.py").is_file():
                raise ConfigError(f"main_dir: no main.py in {self.main_dir}")
            self.firmware_folders = [self.main_dir, *self.app.firmware_path(self.board_path)[1:]]
        self.plant_options = dict(plant_options or {})
        self.plant = plant if plant is not None else self.app.make_plant(**self.plant_options)
        self.plant.reset(seed)
        self._plant_stops_itself = "limit" in inspect.signature(self.plant.advance_to).parameters
        self._uart_wired = False  # a UART configured: bytes flow, the plant advances in chunks
        self.recorder = Recorder(self.plant) if record else None
        self.progress = progress
        self._progress_wall = 0.0
        self._progress_last = None
        self.budgets = {b.name: b for b in self.app.make_budgets()}
        self.artefacts = Path(artefacts) if artefacts else None
        self.trace_enabled = trace
        self.time_round_trips = time_round_trips
        self.stats = RunStats()
        self.console = ""
        self.micropython_version = ""
        self.exit_kind: int | None = None
        self.resets = 0
        self._proc = None
        self._pty = None
        self._chan = None
        self._trace = None
        self._handles: list[Handle] = []
        self._by_signal: dict[str, list[int]] = {}
        self._wait: _Wait | None = None
        self._delta: list = []
        self._delta_bytes = 0
        self._last_batch: list = []
        self._snapshot = None
        self._irq_armed = False
        self._uncommitted: list = []
        self._budgets_by_source: dict[str, list] = {}
        self._compute_budgets = [b for b in self.budgets.values() if isinstance(b, ComputeBudget)]
        for budget in self.budgets.values():
            for source in getattr(budget, "sources", (budget.source,)):
                self._budgets_by_source.setdefault(source, []).append(budget)
        self._sample_times: dict[int, int] = {}
        self._last_type: int | None = None  # of the last message from the shim
        self._wall0 = 0.0

    # -- life cycle -------------------------------------------------------------------

    def __enter__(self):
        self.start()
        return self

    def __exit__(self, *exc):
        self.stop()

    @property
    def t_us(self) -> int:
        return self.plant.t_us

    def start(self) -> "Rig":
        if self.artefacts:
            self.artefacts.mkdir(parents=True, exist_ok=True)
        if self.trace_enabled:
            self._trace = Trace(self.artefacts / "trace.jsonl" if self.artefacts else None)
            self._trace.write(
                {
                    "header": {
                        "app": self.app.name,
                        "board": self.board,
                        "seed": self.seed,
                        "mode": self.mode,
                        "plant": type(self.plant).__name__,
                    }
                }
            )
        self._pty = PtyPair()
        self._spawn()
        return self

    def firmware_env(self) -> dict:
        """The interpreter's environment: shim first, then the firmware's folders as a
        board's filesystem has them, then the frozen modules."""
        folders = [SHIM_DIR, *self.firmware_folders]
        return {
            "PATH": os.environ.get("PATH", "/usr/bin:/bin"),
            "MICROPYPATH": ":".join([*map(str, folders), ".frozen"]),
            "HIL_LINK": self._pty.slave_path,
        }

    def _launch(self) -> None:
        """Start the interpreter; its console is a pipe the link's transport watches."""
        self._proc = subprocess.Popen(
            [str(interpreter.find()), "-m", "_hilboot"],
            env=self.firmware_env(),
            cwd=str(self.main_dir),
            stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            start_new_session=True,
        )
        busy = BUSY_POLL_S if self.mode == "lockstep" and spare_core() else 0.0
        transport = FdTransport(self._pty.master_fd, busy_poll_s=busy)
        transport.watch(self._proc.stdout.fileno(), self._on_console)
        self._chan = Channel(transport)

    def _spawn(self) -> None:
        self._last_type = None
        self._launch()
        self._handles = []
        self._by_signal = {}
        self._wait = None
        self._delta = []
        self._delta_bytes = 0
        self._snapshot = None
        self._irq_armed = False
        type_, payload = self._recv(HANDSHAKE_TIMEOUT_S, "HELLO")
        if type_ != F.HELLO:
            raise LinkError(f"expected HELLO from the shim, got {MSG_NAMES.get(type_, hex(type_))}")
        (proto,) = struct.unpack_from("<H", payload)
        self.micropython_version = payload[2:].decode(errors="replace")
        if proto != F.PROTO_VERSION:
            self.stop()
            raise LinkError(f"shim speaks link protocol {proto}, host speaks {F.PROTO_VERSION}")
        self._send(F.WELCOME, struct.pack("<HBQ", F.PROTO_VERSION, MODES[self.mode], self.t_us))
        self._wall0 = time.monotonic() - self.t_us / 1e6

    def stop(self) -> None:
        """End the firmware process and close the pty; safe to call twice."""
        proc, self._proc = self._proc, None
        if proc is not None:
            if proc.poll() is None:
                try:
                    os.killpg(proc.pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
            try:
                proc.wait(timeout=5)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait(timeout=5)
            if proc.stdout is not None:
                self._drain_console(proc)
                proc.stdout.close()
        if self._pty is not None:
            self._pty.close()
            self._pty = None
        if self._trace is not None:
            self._trace.close()
        if self.artefacts:
            (self.artefacts / "console.log").write_text(self.console)
            if self.recorder is not None:
                write_trace_folder(self, self.artefacts)

    def _drain_console(self, proc) -> None:
        try:
            os.set_blocking(proc.stdout.fileno(), False)
            rest = proc.stdout.read()
            if rest:
                self._on_console(rest)
        except (OSError, ValueError):
            pass

    def _on_console(self, data: bytes) -> None:
        self.console += data.decode(errors="replace")

    @property
    def trace_digest(self) -> str | None:
        return self._trace.digest if self._trace else None

    # -- running --------------------------------------------------------------------

    def _running(self) -> bool:
        return self._proc is not None

    def run_for(self, duration_s: float) -> None:
        self.run_until(self.t_us + round(duration_s * 1e6))

    def run_until(self, t_end_us: int) -> None:
        """Serve the firmware until virtual time reaches ``t_end_us`` (firmware waiting)."""
        if not self._running():
            raise LinkError("the rig is not running: call start() first")
        while True:
            if self.progress is not None:
                self._report_progress(t_end_us)
            if self.exit_kind is not None:  # firmware ended: the plant runs on alone
                while self.t_us < t_end_us:
                    self._advance_plant(t_end_us, frozenset())
                    self._delta = []
                    self._delta_bytes = 0
                self._commit(self.t_us)
                return
            if self._wait is None:
                self._handle(*self._recv(self.watchdog_s, "a message"))
                continue
            if self.t_us >= t_end_us:
                return
            self._serve_wait(t_end_us)

    def _report_progress(self, t_end_us: int) -> None:
        now = time.monotonic()
        if (now >= self._progress_wall or self.t_us >= t_end_us) and self._progress_last != (self.t_us, t_end_us):
            self._progress_wall = now + PROGRESS_EVERY_S
            self._progress_last = (self.t_us, t_end_us)
            self.progress(self.t_us, t_end_us)

    def _serve_wait(self, t_end_us: int) -> None:
        wait = self._wait
        stopped = self._advance_plant(min(wait.t_until, t_end_us), wait.watch)
        if stopped or self.t_us >= wait.t_until:
            self._wait = None
            self._send_state(wait.t_now)
        elif self._snapshot is None:
            self._commit(self.t_us)  # nothing in this batch can be rolled back

    def _advance_plant(self, target_us: int, watch: frozenset) -> bool:
        """Advance the plant, collecting what the firmware must see. True when the batch
        must go now: a watched input changed, the batch is full, or (real time) an IRQ
        edge is due.

        In lockstep IRQ edges are batched speculatively: the plant is snapshotted at the
        start of a batch and rolled back if a handler changes an output (docs/clock.md).
        The plant advances in one go, stopping itself once the batch is full (at the
        recorder's sample times when recording), or in chunks when it cannot stop itself
        or UART bytes flow. A watched wait, and real time, go event by event."""
        plant = self.plant
        lockstep = self.mode == "lockstep"
        if lockstep and self._snapshot is None and self._wait is not None and self._irq_armed:
            self._snapshot = (plant.t_us, self._take_snapshot())
        while plant.t_us < target_us:
            limit = 0
            if lockstep and not watch:
                if self._plant_stops_itself and not self._uart_wired:
                    t_next = target_us
                    if self.recorder is not None:
                        t_next = min(t_next, max(self.recorder.next_truth_us, plant.t_us + 1))
                    fan_out = max(map(len, self._by_signal.values()), default=1)  # handles per signal
                    limit = max(1, (MAX_BATCH - len(self._delta)) // max(1, fan_out))
                else:
                    t_next = min(plant.t_us + CHUNK_US, target_us)
            else:
                t_next = min(plant.next_change_us(), target_us)
                if not lockstep:
                    self._sleep_until(t_next)
            irq = hit = False
            for change in plant.advance_to(t_next, limit) if limit else plant.advance_to(t_next):
                i, h = self._route(change, watch)
                irq |= i
                hit |= h
            if self.recorder is not None:
                self.recorder.sample(plant)
            if hit or (irq and not lockstep) or len(self._delta) >= MAX_BATCH or self._delta_bytes > MAX_BATCH_BYTES:
                return True
        return False

    def _take_snapshot(self):
        if hasattr(self.plant, "snapshot"):  # a plant may know its state best
            return self.plant.snapshot()
        gens: list = []
        return _copy_state(self.plant.__dict__, gens), [(g, g.bit_generator.state) for g in gens]

    def _restore_snapshot(self, snap) -> None:
        if hasattr(self.plant, "restore"):
            self.plant.restore(snap)
            return
        state, gens = snap
        self.plant.__dict__.clear()
        self.plant.__dict__.update(state)
        for gen, gen_state in gens:
            gen.bit_generator.state = gen_state

    def _rewind(self, t_us: int) -> None:
        """A handler changed an output at t_us inside a speculative batch: go back."""
        if self._snapshot is None or self._snapshot[0] > t_us:
            raise LinkError(
                f"firmware reported t={t_us} us, before the plant's {self.t_us} us, with no snapshot to "
                f"return to (link protocol error)"
            )
        self._restore_snapshot(self._snapshot[1])
        self.plant.advance_to(t_us)  # the firmware already has these changes
        if self.recorder is not None:
            self.recorder.rewind(t_us)
        self._snapshot = None
        self._uncommitted = [e for e in self._uncommitted if e[0] <= t_us]
        for t, h, kind, _value, extra in self._last_batch:
            if t > t_us and h < len(self._handles):
                if kind == F.CH_SAMPLE:
                    self._handles[h].samples -= 1
                elif kind == F.CH_BYTES:
                    self._handles[h].samples -= extra.count(b"\n")
        self.stats.rollbacks += 1
        self._log({"t": t_us, "msg": "ROLLBACK"})

    def _sleep_until(self, t_us: int) -> None:
        delay = self._wall0 + t_us / 1e6 - time.monotonic()
        if delay > 0:
            time.sleep(delay)

    def _route(self, change, watch: frozenset) -> tuple[bool, bool]:
        """Queue a plant change for the firmware; (fires an IRQ, wakes a watched wait)."""
        t, name, value = change
        irq = hit = False
        if self.recorder is not None:
            self.recorder.sensor(t, name, value)
        for budget in self._budgets_by_source.get(name, ()):
            if isinstance(budget, PeriodBudget) and budget.counts(value):
                self._uncommitted.append((t, budget.event, (t,)))
        for h in self._by_signal.get(name, ()):
            info = self._handles[h]
            if info.kind == F.CFG_ADC:
                info.samples += 1
                for budget in self._budgets_by_source.get(name, ()):
                    if isinstance(budget, LatencyBudget):
                        self._uncommitted.append((t, budget.sample, (info.samples, t)))
                self._delta.append((t, h, F.CH_SAMPLE, value, info.samples))
            elif info.kind == F.CFG_UART:
                for _ in range(value.count(b"\n")):  # a line is a sample (the shim counts them too)
                    info.samples += 1
                    for budget in self._budgets_by_source.get(name, ()):
                        if isinstance(budget, LatencyBudget):
                            self._uncommitted.append((t, budget.sample, (info.samples, t)))
                self._delta.append((t, h, F.CH_BYTES, len(value), value))
                self._delta_bytes += len(value)
                hit |= h in watch
            else:
                self._delta.append((t, h, F.CH_LEVEL, value, 0))
                if h in watch:
                    hit = True
                elif info.irq & (1 if value else 2):
                    irq = True
                    self.stats.irq_edges += 1
        return irq, hit

    def _commit(self, t_us: int) -> None:
        """Budget events up to t_us can no longer be rolled back: record them."""
        if self._uncommitted and self._uncommitted[0][0] <= t_us:
            keep = []
            for event in self._uncommitted:
                if event[0] <= t_us:
                    event[1](*event[2])
                else:
                    keep.append(event)
            self._uncommitted = keep

    def _send_state(self, base_us: int) -> None:
        horizon = self.plant.next_change_us()
        parts = [struct.pack("<QQQH", base_us, self.t_us, horizon, len(self._delta))]
        for t, h, kind, value, extra in self._delta:
            dt = t - base_us if t > base_us else 0
            if kind == F.CH_BYTES:
                parts.append(struct.pack("<IHBiI", dt, h, kind, value, 0) + extra)
            else:
                parts.append(struct.pack("<IHBiI", dt, h, kind, value, extra))
        if self._trace:
            self._trace.write(
                {
                    "t": self.t_us,
                    "to": "fw",
                    "msg": "STATE",
                    "base": base_us,
                    "horizon": horizon,
                    "changes": [[t, h, k, v, e.hex() if k == F.CH_BYTES else e] for t, h, k, v, e in self._delta],
                }
            )
        self._last_batch = self._delta
        self._delta = []
        self._delta_bytes = 0
        self._send(F.STATE, b"".join(parts))
        self.stats.link_round_trips += 1

    # -- messages from the firmware ------------------------------------------------------

    def _handle(self, type_: int, p: bytes) -> None:
        if type_ == F.OUT:
            t, h, attr, value = _OUT.unpack_from(p)
            if t != self.plant.t_us:
                self._catch_up(t)
            self._on_out(t, h, attr, value)
        elif type_ == F.WAIT:
            t_now, t_until, compute_us = _WAIT.unpack_from(p)
            watch = frozenset(struct.unpack_from("<%dH" % ((len(p) - 20) // 2), p, 20)) if len(p) > 20 else _NO_WATCH
            self._catch_up(t_now)
            self._snapshot = None  # the firmware took the whole last batch
            self._commit(t_now)
            self._wait = _Wait(t_now, max(t_until, self.t_us), watch)
            for budget in self._compute_budgets:
                budget.event(compute_us)
            if self._trace:
                self._log({"t": t_now, "msg": "WAIT", "until": t_until, "watch": sorted(watch)})
        elif type_ == F.CFG:
            self._on_cfg(p)
        elif type_ == F.SEEN:
            t, h, sample_no = struct.unpack_from("<QHI", p)
            self._commit(t)
            signal_name = self._handles[h].signal
            for budget in self.budgets.values():
                if isinstance(budget, LatencyBudget) and budget.source == signal_name:
                    budget.seen(sample_no, t)
            self._log({"t": t, "msg": "SEEN", "handle": h, "sample": sample_no})
        elif type_ == F.UART_TX:
            t, h = struct.unpack_from("<QH", p)
            self._catch_up(t)
            signal_name = self._handles[h].signal
            if self.recorder is not None:
                self._record_out(t, self._handles[h], p[10:], "bytes")
            if signal_name in self.plant.inputs:
                self.plant.set_input(signal_name, p[10:])
            self._log({"t": t, "msg": "UART_TX", "handle": h, "data": p[10:].hex()})
        elif type_ == F.FAULT:
            self._on_fault(p)
        elif type_ == F.EXIT:
            t, kind, code = struct.unpack_from("<QBi", p)
            self._log({"t": t, "msg": "EXIT", "kind": kind, "code": code})
            if kind == F.EXIT_RESET:
                self._restart()
            else:
                self.exit_kind = kind
                self._catch_up(t)
        else:
            raise LinkError(f"unexpected message type 0x{type_:02x} from the shim")

    def _catch_up(self, t_us: int) -> None:
        """Bring the plant to the firmware's time: forward if the shim moved on inside
        its horizon, back if a handler changed an output inside a speculative batch."""
        if t_us > self.t_us:
            for change in self.plant.advance_to(t_us):
                self.stats.lease_violations += 1
                self._route(change, frozenset())
            if self.recorder is not None:
                self.recorder.sample(self.plant)
        elif t_us < self.t_us and self.mode == "lockstep":
            self._rewind(t_us)  # (in real time the two clocks differ by the link's latency: no rewind)
        self._commit(t_us)

    def _on_cfg(self, p: bytes) -> None:
        h, kind, mode, pull, param = struct.unpack_from("<HBBBi", p)
        key = p[9:].decode()
        board_name = self.pin_names.get(key)
        signal_name = self.app.wiring.get(board_name) if board_name else None
        self._log(
            {
                "t": self.t_us,
                "msg": "CFG",
                "handle": h,
                "kind": CFG_KINDS.get(kind, kind),
                "pin": key,
                "mode": mode,
                "pull": pull,
                "param": param,
                "signal": signal_name,
            }
        )
        if kind == F.CFG_UART:
            self._uart_wired = True
        if kind == F.CFG_IRQ:
            self._handles[h].irq = mode
            self._irq_armed = any(info.irq for info in self._handles)
            return
        while len(self._handles) <= h:
            self._handles.append(Handle(0, "", None, None))
        is_input = kind == F.CFG_ADC or (kind == F.CFG_PIN and mode == 0)
        info = Handle(kind, key, board_name, signal_name, is_input=is_input, pull=pull)
        old = self._handles[h]
        if old.signal and h in self._by_signal.get(old.signal, ()):
            self._by_signal[old.signal].remove(h)
        self._handles[h] = info
        if signal_name:
            self._by_signal.setdefault(signal_name, []).append(h)
        if info.is_input:  # the shim syncs next: tell it the current level
            if signal_name in self.plant.outputs:
                value = self.plant.output(signal_name)
            else:
                value = 1 if pull == 1 else 0
            kind_ = F.CH_SAMPLE if kind == F.CFG_ADC else F.CH_LEVEL
            self._delta.append((self.t_us, h, kind_, value if value is not None else 0, 0))

    def _on_out(self, t: int, h: int, attr: int, value: int) -> None:
        info = self._handles[h]
        signal_name = info.signal
        if self._trace:
            self._log({"t": t, "msg": "OUT", "handle": h, "attr": OUT_ATTRS.get(attr, attr), "value": value})
        if self.recorder is not None and attr != F.OUT_FREQ:
            kind = "duty" if info.kind == F.CFG_PWM else "level"
            self._record_out(t, info, 0 if attr == F.OUT_DEINIT else value, kind)
        if signal_name is None:
            return
        if signal_name.startswith(PROBE):
            last, info.level = info.level, value
            if attr == F.OUT_LEVEL and last is not None and last != value:
                for budget in self._budgets_by_source.get(signal_name, ()):
                    if isinstance(budget, PeriodBudget):
                        budget.event(t)
            return
        if signal_name not in self.plant.inputs:
            return
        if attr == F.OUT_LEVEL:
            for budget in self._budgets_by_source.get(signal_name, ()):
                if isinstance(budget, PulseBudget):
                    budget.output(t, signal_name, value)
        if info.kind == F.CFG_PWM:
            if attr == F.OUT_DUTY:
                self.plant.set_input(signal_name, value)
            elif attr == F.OUT_DEINIT:
                self.plant.set_input(signal_name, 0)
        elif attr == F.OUT_LEVEL:
            self.plant.set_input(signal_name, value)

    def _record_out(self, t: int, info: Handle, value, kind: str) -> None:
        """A firmware output, as the plant's input (or the probe, or the bare pin) saw it."""
        if info.signal and info.signal.startswith(PROBE):
            self.recorder.command(t, info.signal, value, role=PROBE_ROLE, kind=kind)
        elif info.signal in self.plant.inputs:
            self.recorder.command(t, info.signal, value, role=ACTUATOR, kind=kind)
        else:
            self.recorder.command(t, f"pin.{info.board_name or info.key}", value, role=PIN, kind=kind)

    def _on_fault(self, p: bytes) -> None:
        (t,) = struct.unpack_from("<Q", p)
        text = p[8:].decode(errors="replace")
        self._log({"t": t, "msg": "FAULT"})
        try:
            self._recv(1.0, "EXIT")  # let the process finish writing
        except (LinkError, FirmwareError):
            pass
        self.stop()
        raise FirmwareError(
            f"firmware raised at virtual t={t / 1e6:.6f} s; expected it to keep running.\n"
            f"MicroPython traceback:\n{text.rstrip()}{self._where()}",
            traceback=text,
            console=self.console,
        )

    def _restart(self) -> None:
        """machine.reset(): the board restarts its interpreter; the plant carries on."""
        self.resets += 1
        proc, self._proc = self._proc, None
        proc.wait(timeout=5)
        if proc.stdout is not None:
            self._drain_console(proc)
            proc.stdout.close()
        self._spawn()

    # -- link ------------------------------------------------------------------------

    def _send(self, type_: int, payload: bytes) -> None:
        try:
            self._chan.send(type_, payload)
        except OSError as e:
            raise LinkError(f"plant link write failed: {e}") from e
        if self.time_round_trips:
            self._t_sent = time.perf_counter()

    def _recv(self, timeout_s: float, what: str):
        try:
            type_, _seq, payload = self._chan.recv(timeout_s)
        except LinkTimeout:
            self._on_silence(timeout_s, what)
        except LinkError:
            self._on_silence(0, what)
        if self.time_round_trips and type_ == F.WAIT and getattr(self, "_t_sent", None):
            self.stats.round_trip_us.append((time.perf_counter() - self._t_sent) * 1e6)
            self._t_sent = None
        self._last_type = type_
        return type_, payload

    def _last_msg_text(self) -> str:
        if self._last_type is None:
            return "none yet"
        name = MSG_NAMES.get(self._last_type, hex(self._last_type))
        wall = self._chan.last_data_wall if self._chan else None
        return name if wall is None else f"{name}, read at wall {wall:.3f}"

    def _on_silence(self, timeout_s: float, what: str):
        proc = self._proc
        if proc is not None and proc.poll() is None and timeout_s > 0:
            self.stop()
            raise FirmwareHung(
                f"firmware stopped answering: expected {what} within {timeout_s:g} s of wall time, "
                f"got nothing (virtual t={self.t_us / 1e6:.6f} s, last message {self._last_msg_text()}); "
                f"the watchdog stopped it.{self._where()}"
            )
        code = proc.wait(timeout=5) if proc is not None else None
        self.stop()
        raise FirmwareError(
            f"firmware process ended with exit code {code} while the host expected {what} "
            f"(virtual t={self.t_us / 1e6:.6f} s).{self._where()}",
            console=self.console,
        )

    def _log(self, record: dict) -> None:
        if self._trace:
            self._trace.write(record)

    def _where(self) -> str:
        tail = "\n".join(self.console.rstrip().splitlines()[-CONSOLE_TAIL_LINES:])
        where = f"\nartefacts: {self.artefacts}" if self.artefacts else ""
        return (f"\nconsole (last {CONSOLE_TAIL_LINES} lines):\n{tail}" if tail else "\nconsole: (empty)") + where

    # -- results ---------------------------------------------------------------------

    def truth(self) -> dict:
        return self.plant.truth()

    def budget_rows(self) -> list[dict]:
        return [b.stats() for b in self.budgets.values()]

    def counters(self) -> dict:
        link = self._chan.counters() if self._chan else {}
        return {
            **link,
            "round_trips": self.stats.link_round_trips,
            "irq_edges": self.stats.irq_edges,
            "rollbacks": self.stats.rollbacks,
            "lease_violations": self.stats.lease_violations,
        }
