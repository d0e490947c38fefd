"""``mpy-fil mcp``: a live rig's operations (``docs/live.md``) as Model Context Protocol
tools over stdio, with the ``mcp`` SDK's server: start a rig from a rig file, run it until
an instant, a console line or a pin's level, read its pins, console, truth, budgets and bus
log, read or run a line in the paused firmware, set a control, press a button, inject a
fault, take and restore snapshots, plot its trace folder, stop it.

Limits (:class:`Limits`, the command's options): rigs open at once, simulated seconds in
one call, wall seconds over all of one rig's calls. The firmware runs as in any run,
confined to its board. The server writes nothing on stdout but the protocol's messages."""

import dataclasses
import math
import shutil
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from mcp.server.mcpserver import Image, MCPServer
from mcp.server.mcpserver.exceptions import ToolError

from host.core.errors import HarnessError
from host.live.live import LiveRig

INSTRUCTIONS = (
    "Firmware in the loop: MicroPython firmware against a simulated robot, in virtual time that stands "
    "still between calls. start a rig from its rig file, run_until an instant, a console line or a pin "
    "level, look (pins, console, truth, budgets, eval), poke (set_control, press, inject, exec), "
    "snapshot and restore, stop. Times: t_s in simulated seconds, *_us in virtual microseconds."
)


@dataclass(frozen=True)
class Limits:
    max_rigs: int = 1  # rigs open at once
    max_run_s: float = 60.0  # simulated seconds one call may run
    max_wall_s: float = 300.0  # wall seconds all of one rig's calls may take


@dataclass
class Served:
    """One rig the server runs, with what its caller was given of it."""

    live: LiveRig
    wall_s: float = 0.0  # spent in its calls so far
    snapshots: list = field(default_factory=list)
    console_from: int = 0  # console bytes already returned by a run


def plain(value):
    """``value`` as JSON's types: numbers, text, lists and objects (a contact, a numpy
    number: their fields, their value)."""
    if isinstance(value, dict):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)) and not hasattr(value, "_asdict"):
        return [plain(v) for v in value]
    if hasattr(value, "_asdict"):
        return plain(value._asdict())
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return plain(dataclasses.asdict(value))
    if hasattr(value, "item") and callable(value.item):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return str(value)
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    return repr(value)


class Rigs:
    """The server's rigs by id, each call held to the limits; a harness error becomes the
    tool's error, its message whole."""

    def __init__(self, limits: Limits, out: Path):
        self.limits = limits
        self.out = out
        self.open: dict[str, Served] = {}
        self.started = 0

    def start(self, app: str, record: bool, **spec) -> str:
        if len(self.open) >= self.limits.max_rigs:
            raise ToolError(
                f"{len(self.open)} rig(s) open, at most {self.limits.max_rigs} (mpy-fil mcp --max-rigs): stop one first"
            )
        self.started += 1
        rig_id = f"rig{self.started}"
        artefacts = self.out / rig_id if record else None
        try:
            live = LiveRig.start(app, record=record, artefacts=artefacts, **spec)
        except (HarnessError, ValueError, TypeError) as e:
            raise ToolError(f"cannot start {app}: {e}") from None
        self.open[rig_id] = Served(live)
        return rig_id

    def get(self, rig_id: str) -> Served:
        served = self.open.get(rig_id)
        if served is None:
            raise ToolError(f"no rig {rig_id!r} open (open: {', '.join(self.open) or 'none'})")
        return served

    def call(self, rig_id: str, action, run_s: float = 0.0):
        """``action(live)`` under the limits: ``run_s`` the simulated seconds it may run."""
        served = self.get(rig_id)
        if run_s > self.limits.max_run_s:
            raise ToolError(f"{run_s:g} simulated s in one call; at most {self.limits.max_run_s:g} (--max-run-s)")
        left_s = self.limits.max_wall_s - served.wall_s
        if left_s <= 0:
            raise ToolError(f"{rig_id} has spent its {self.limits.max_wall_s:g} wall s (--max-wall-s): stop it")
        live, t0 = served.live, time.monotonic()
        live.wall_deadline = t0 + left_s
        try:
            return action(live)
        except (HarnessError, ValueError, AssertionError) as e:
            raise ToolError(f"{type(e).__name__}: {e}") from None
        finally:
            live.wall_deadline = None
            served.wall_s += time.monotonic() - t0

    def news(self, rig_id: str) -> str:
        """The console since the last run call's answer."""
        served = self.get(rig_id)
        text, start = served.live.rig.console_log.since(served.console_from)
        served.console_from = start + len(text.encode())
        return text

    def stop(self, rig_id: str) -> None:
        served = self.open.pop(rig_id, None)
        if served is not None:
            served.live.stop()

    def close(self) -> None:
        for rig_id in list(self.open):
            self.stop(rig_id)


def make_server(limits: Limits, out: Path) -> tuple[MCPServer, Rigs]:
    server = MCPServer("mpy-fil", instructions=INSTRUCTIONS)
    rigs = Rigs(limits, out)
    _running_tools(server, rigs)
    _looking_tools(server, rigs)
    _poking_tools(server, rigs)
    return server, rigs


def _ran(rigs: Rigs, rig_id: str, **more) -> dict:
    return {"t_us": rigs.get(rig_id).live.t_us, **more, "console": rigs.news(rig_id)}


def _running_tools(server: MCPServer, rigs: Rigs) -> None:
    @server.tool()
    async def start(
        rig: str,
        seed: int = 0,
        world: str | None = None,
        options: dict | None = None,
        faults: list[dict] | None = None,
        record: bool = False,
    ) -> dict[str, Any]:
        """Start a rig: RIG is a rig file (or its folder, or one of mpy-fil's apps by name). The
        firmware boots and waits at its first instant; record=True keeps a trace folder (plots)."""
        rig_id = rigs.start(rig, record, seed=seed, world=world, options=options or {}, faults=faults or [])
        live = rigs.get(rig_id).live
        return {"rig_id": rig_id, "seed": live.seed, "board": live.rig.board, "t_us": live.t_us}

    @server.tool()
    async def run_until(
        rig_id: str,
        t_s: float | None = None,
        console: str | None = None,
        pin: str | None = None,
        level: int = 1,
        timeout_s: float = 10.0,
    ) -> dict[str, Any]:
        """Run until virtual time t_s (absolute, simulated seconds), the console matching the regular
        expression CONSOLE, or PIN (GP25, a rig pin name, a plant signal) at LEVEL, at most timeout_s
        simulated s; the time and the console's new text back."""
        live = rigs.get(rig_id).live
        run_s = (t_s - live.t_us / 1e6) if t_s is not None else timeout_s
        found = rigs.call(
            rig_id, lambda lv: lv.run_until(t_s=t_s, console=console, pin=pin, level=level, timeout_s=timeout_s), run_s
        )
        return _ran(rigs, rig_id, matched=found.group(0) if console is not None else None)

    @server.tool()
    async def step(rig_id: str, ms: float) -> dict[str, Any]:
        """Run MS milliseconds of virtual time more."""
        rigs.call(rig_id, lambda lv: lv.step(round(ms * 1000)), ms / 1000)
        return _ran(rigs, rig_id)

    @server.tool()
    async def snapshot(rig_id: str) -> dict[str, Any]:
        """This instant, to restore later: its number back."""
        served = rigs.get(rig_id)
        served.snapshots.append(served.live.snapshot())
        return {"snapshot": len(served.snapshots) - 1, "t_us": served.live.t_us}

    @server.tool()
    async def restore(rig_id: str, snapshot: int) -> dict[str, Any]:
        """Back to a snapshot's instant, firmware included (the calls that led there replayed)."""
        served = rigs.get(rig_id)
        if not 0 <= snapshot < len(served.snapshots):
            raise ToolError(f"no snapshot {snapshot} of {rig_id} (taken: {len(served.snapshots)})")
        rigs.call(rig_id, lambda lv: lv.restore(served.snapshots[snapshot]))
        served.console_from = served.live.rig.console_log.total_bytes
        return {"t_us": served.live.t_us}

    @server.tool()
    async def stop(rig_id: str) -> dict[str, Any]:
        """End the rig (its trace folder written when it records)."""
        t_us = rigs.get(rig_id).live.t_us
        rigs.stop(rig_id)
        return {"stopped": rig_id, "t_us": t_us}

    @server.tool(structured_output=False)
    async def plots(rig_id: str) -> list[Image]:
        """The trace folder's plots as PNG images; the rig (started with record=True) stops first."""
        from host.report.plots import plot_trace

        live = rigs.get(rig_id).live
        folder = live.recording.artefacts
        if not live.recording.record or folder is None:
            raise ToolError(f"{rig_id} does not record: start it with record=true for plots")
        rigs.stop(rig_id)
        return [Image(path=path) for path in plot_trace(folder)]


def _looking_tools(server: MCPServer, rigs: Rigs) -> None:
    @server.tool()
    async def pins(rig_id: str) -> dict[str, Any]:
        """Every pin, PWM, ADC and UART the firmware configured: kind, mode, signal, level, duty."""
        return plain(rigs.get(rig_id).live.pins())

    @server.tool()
    async def console(rig_id: str, lines: int = 40) -> str:
        """The console's last LINES lines."""
        return rigs.get(rig_id).live.console(lines=lines)

    @server.tool()
    async def truth(rig_id: str) -> dict[str, Any]:
        """The plant's ground truth now (pose, contacts, ...)."""
        return plain(rigs.get(rig_id).live.truth())

    @server.tool()
    async def budgets(rig_id: str) -> dict[str, Any]:
        """Each timing budget's statistics so far (count, p50, p95, p99, min, max, misses; µs)."""
        return plain(rigs.get(rig_id).live.budgets())

    @server.tool()
    async def bus_log(rig_id: str, since_us: int = 0) -> dict[str, Any]:
        """The I2C/SPI transactions since SINCE_US."""
        return {"transactions": plain(rigs.get(rig_id).live.bus_log(since_us))}

    @server.tool(name="eval")
    async def eval_(rig_id: str, expression: str) -> dict[str, Any]:
        """Read a firmware global or a module's attribute (motor.duty) in the paused firmware;
        virtual time does not move."""
        return {"value": plain(rigs.call(rig_id, lambda lv: lv.eval(expression)))}


def _poking_tools(server: MCPServer, rigs: Rigs) -> None:
    @server.tool(name="exec")
    async def exec_(rig_id: str, line: str) -> dict[str, Any]:
        """Run a REPL line in the paused firmware's globals (it may not drive pins or wait)."""
        return {"echo": rigs.call(rig_id, lambda lv: lv.exec(line))}

    @server.tool()
    async def set_control(rig_id: str, part: str, control: str, value: float | int | str) -> dict[str, Any]:
        """Set a part's control from now on (a button's pressed, a sonar's distance in cm, ...)."""
        rigs.call(rig_id, lambda lv: lv.set(part, control, value))
        return {"t_us": rigs.get(rig_id).live.t_us}

    @server.tool()
    async def press(rig_id: str, button: str, ms: float = 100) -> dict[str, Any]:
        """Press a button part for MS milliseconds of virtual time (the rig runs), then let go."""
        rigs.call(rig_id, lambda lv: lv.press(button, ms), ms / 1000)
        return _ran(rigs, rig_id)

    @server.tool()
    async def inject(rig_id: str, fault: dict) -> dict[str, Any]:
        """A fault from now on, as a rig file's [[faults]] entry ({"kind": "stuck", "signal": ..., "value": 0})."""
        return {"injected": plain(rigs.call(rig_id, lambda lv: lv.inject(fault))), "t_us": rigs.get(rig_id).live.t_us}

    @server.tool()
    async def uart_write(rig_id: str, text: str) -> dict[str, Any]:
        """Type TEXT on the board's console input (the firmware's sys.stdin)."""
        rigs.call(rig_id, lambda lv: lv.uart_write(text))
        return {"t_us": rigs.get(rig_id).live.t_us}


def serve(limits: Limits, out: Path | None = None) -> None:
    """Serve over stdio until the client goes; every rig stopped then, the temporary
    folder of recorded rigs (when ``out`` is None) removed."""
    folder = Path(tempfile.mkdtemp(prefix="mpy-fil-mcp-")) if out is None else out
    server, rigs = make_server(limits, folder)
    try:
        server.run("stdio")
    finally:
        rigs.close()
        if out is None:
            shutil.rmtree(folder, ignore_errors=True)
