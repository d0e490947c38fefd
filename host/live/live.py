"""A rig driven call by call (``docs/live.md``): run to an instant, a console line or a
pin's level; look at pins, buses, the truth, the budgets, the console and the firmware's
own variables; set a control, press a button, inject a fault, type on the console; take a
snapshot and go back to it. Everything goes through the :class:`~host.rig.Rig` and the
parts it already has (the scenario runner's controls and console input, the fault
schedule, the budgets); this class adds only the journal that makes a snapshot
(:mod:`host.live.journal`). A plain run never comes here."""

import ast
import time
from collections import deque

from host.core.errors import ConfigError, HarnessError
from host.link import frames as F
from host.live import journal, look
from host.rig import Rig
from host.rig.config import arguments
from host.rig.loop import waits
from host.rig.loop.introspect import FirmwareEvalError
from host.rig.loop.spec import NO_RECORDING, Recording, RigSpec

PIN_STEP_S = 0.001  # simulated seconds between two looks at a pin (a board's system tick)
BUS_LOG_MAX = 10_000  # transactions a live rig keeps (the trace keeps them all)
WALL_CHUNK_US = 100_000  # with a wall deadline, a run goes in pieces this long, the deadline looked at between


class WallLimit(HarnessError):
    """A live rig's call ran past the wall time it was given (``LiveRig.wall_deadline``)."""


class LiveRig:
    """One rig, started, served only when asked. ``LiveRig.start("rig.toml", seed=1)``
    (or one of our apps by name); use as a context manager, or call :meth:`stop`."""

    def __init__(self, spec: RigSpec, recording: Recording = NO_RECORDING):
        self.spec = spec  # (its seed drawn once, here: every replay runs with it)
        self.recording = recording
        self.entries: list[tuple] = []
        self.bus: deque = deque(maxlen=BUS_LOG_MAX)
        self.rig: Rig | None = None
        self.wall_deadline: float | None = None  # time.monotonic() past which a run stops (mpy-fil mcp's limit)
        self._begin(spec)

    @classmethod
    def start(cls, app, *, trace: bool = True, record: bool = False, artefacts=None, **spec) -> "LiveRig":
        """A live rig of ``app`` (a rig file, its folder, or one of our apps by name);
        ``spec``: :class:`RigSpec`'s fields (``seed``, ``world``, ``options``, ``faults``, ...).
        ``trace`` keeps the link trace's digest (:attr:`trace_digest`)."""
        return cls(RigSpec(str(app), **spec), Recording(trace=trace, record=record, artefacts=artefacts))

    def _begin(self, spec: RigSpec) -> None:
        self.bus.clear()
        rig = Rig(spec, self.recording)
        rig.bus_trace.tap = lambda tx: self.bus.append(look.transaction(tx))
        self.rig = rig.start()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.stop()

    def stop(self) -> None:
        """End the firmware; the trace folder is written when the rig records (safe twice)."""
        if self.rig is not None:
            self.rig.stop()

    @property
    def t_us(self) -> int:
        return self.rig.t_us

    @property
    def seed(self) -> int:
        return self.spec.seed

    @property
    def trace_digest(self) -> str | None:
        return self.rig.trace_digest

    # -- running ----------------------------------------------------------------------

    def _do(self, entry: tuple):
        """Give the rig ``entry`` and journal it (once it was taken)."""
        try:
            result = journal.apply(self.rig, entry)
        except FirmwareEvalError:
            self.entries.append(entry)  # (it ran in the firmware, up to its error: a replay runs it too)
            raise
        self.entries.append(entry)
        return result

    def _to(self, t_us: int) -> None:
        if self.wall_deadline is not None and time.monotonic() > self.wall_deadline:
            raise WallLimit(f"stopped at virtual t={self.t_us / 1e6:.6f} s: the wall time given to this rig is spent")
        self._do(("to", int(t_us)))

    def run_until(
        self,
        *,
        t_s: float | None = None,
        t_us: int | None = None,
        console: str | None = None,
        pin: str | None = None,
        level: int = 1,
        timeout_s: float = 10.0,
    ):
        """Serve the firmware until one thing is so: virtual time at ``t_s`` (or ``t_us``,
        absolute), the console matching the regular expression ``console`` (after what the
        last match took: the match back), or ``pin`` at ``level`` (looked at every ms of
        virtual time: the level back). ``timeout_s`` caps a console or pin wait in
        simulated seconds: ExpectTimeout after it."""
        asked = (("t_s", t_s), ("t_us", t_us), ("console", console), ("pin", pin))
        given = [name for name, value in asked if value is not None]
        if len(given) != 1:
            raise ConfigError(f"run_until: expected one of t_s, t_us, console, pin; got {given or 'none'}")
        if t_s is not None or t_us is not None:
            end_us = t_us if t_us is not None else round(arguments.seconds("run_until t_s", t_s) * 1e6)
            if end_us > self.t_us + round(arguments.MAX_RUN_S * 1e6):
                raise ConfigError(f"run_until: at most {arguments.MAX_RUN_S:g} simulated s in one call")
            if self.wall_deadline is None:
                self._to(max(end_us, self.t_us))
            while self.t_us < end_us:
                self._to(min(end_us, self.t_us + WALL_CHUNK_US))
            return self.t_us
        if console is not None:
            return waits.expect(self.rig, console, timeout_s, advance=self._to)
        want = int(level)
        look.level(self.rig, pin)  # (a pin nobody knows: said now, not after the timeout)
        reached = lambda: look.level(self.rig, pin) == want  # noqa: E731
        reached.__name__ = f"{pin} at level {want}"
        waits.until(self.rig, reached, timeout_s, PIN_STEP_S, advance=self._to)
        return want

    def step(self, us: int) -> int:
        """Serve the firmware ``us`` µs of virtual time more; the time then."""
        return self.run_until(t_us=self.t_us + int(us))

    # -- looking ---------------------------------------------------------------------

    def pins(self) -> dict[str, dict]:
        """The firmware's pins now (:func:`host.live.look.pins`)."""
        return look.pins(self.rig)

    def pin(self, pin: str) -> int:
        """One pin's level now: a board pin (``GP25``, ``LED``) or a plant signal."""
        return look.level(self.rig, pin)

    def bus_log(self, since_us: int = 0) -> list[dict]:
        """The bus transactions since ``since_us`` (the last BUS_LOG_MAX of them)."""
        return [tx for tx in self.bus if tx["t_us"] >= since_us]

    def truth(self) -> dict:
        return self.rig.truth()

    def budgets(self) -> dict[str, dict]:
        """Each budget's statistics so far (count, p50, p95, p99, min, max, misses; µs)."""
        return {name: budget.stats() for name, budget in self.rig.budgets.items()}

    def console(self, lines: int | None = None) -> str:
        """What the firmware printed (its last ``lines`` lines)."""
        text = self.rig.console
        return text if lines is None else "".join(text.splitlines(keepends=True)[-lines:])

    # -- the firmware's own state ---------------------------------------------------

    def _paused(self) -> None:
        if self.rig.clock.wait is None and self.rig.exit_kind is None:
            self._to(self.t_us)  # (to the firmware's first wait: it booted, it waits)

    def eval(self, expression: str):
        """A firmware global or a module's attribute (``"motor.duty"``) at this instant,
        without moving virtual time: a Python value when its repr is a literal, else the
        repr's text. FirmwareEvalError when it raises in the firmware."""
        self._paused()
        text = self._do(("eval", False, expression))[1]
        try:
            return ast.literal_eval(text)
        except (ValueError, SyntaxError, MemoryError, RecursionError):
            return text

    def exec(self, line: str) -> str | None:
        """A REPL line run in the paused firmware's globals (``"speed = 0.2"``); an
        expression's repr back, as the REPL echoes it, else None. It may not drive the
        board or wait (the shim refuses)."""
        self._paused()
        status, text = self._do(("eval", True, line))
        return text if status == F.EVAL_VALUE else None

    # -- pokes ---------------------------------------------------------------------

    def set(self, part: str, control: str, value) -> None:
        """A part's control from now on (``sim_plant.controls``: a button's ``pressed``, a
        sonar's ``distance``, an IMU's ``accelX``...)."""
        self._do(("set", part, control, value))

    def press(self, button: str, ms: float = 100) -> None:
        """Press ``button`` for ``ms`` of virtual time (the rig runs that long), then let go."""
        self.set(button, "pressed", 1)
        self.step(round(ms * 1000))
        self.set(button, "pressed", 0)

    def uart_write(self, data: bytes | str) -> None:
        """Bytes on the board's console input (the firmware's ``sys.stdin``), now."""
        self._do(("stdin", data.encode() if isinstance(data, str) else bytes(data)))

    def inject(self, fault: dict) -> dict:
        """A fault from now on (``sim_plant.faults``: ``{"kind": "stuck", "signal":
        "start.out", "value": 0}``; its window starts now unless it says later). The run
        so far is replayed with the fault in the rig's schedule; the entry as injected back."""
        entry = look.fault_at(fault, self.t_us, self.rig.plant)
        self.entries.append(("fault", entry))
        self._replay(len(self.entries))
        return entry

    # -- snapshots -------------------------------------------------------------------

    def snapshot(self) -> journal.Snapshot:
        """This instant, to come back to with :meth:`restore`."""
        return journal.Snapshot(self.t_us, len(self.entries), self.trace_digest)

    def restore(self, snapshot: journal.Snapshot) -> None:
        """Back to ``snapshot``'s instant, firmware included: the rig starts again and the
        calls that led there are replayed (what came after is forgotten)."""
        if snapshot.entries > len(self.entries):
            raise ConfigError("restore: that snapshot is not on this rig's course (a later one was restored since)")
        self._replay(snapshot.entries)

    def _replay(self, n_entries: int) -> None:
        entries = self.entries[:n_entries]
        self.rig.stop()
        spec = self.spec.replace(faults=[*self.spec.fault_entries, *journal.faults(entries)])
        self._begin(spec)
        journal.replay(self.rig, entries)
        self.entries = entries
