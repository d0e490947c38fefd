"""The rig: MicroPython + shim + firmware + plant, run in lockstep virtual time.

A :class:`Rig` starts the firmware on its target (by default MicroPython's unix port
with the shim first on ``MICROPYPATH`` and the firmware's folders after it, as a board's
filesystem has them), shakes hands over the link, and then serves the shim: actuator
writes go to the plant at their virtual time; a WAIT advances the plant to the time
asked for, or to the first edge that fires a registered IRQ, and answers with the
inputs that changed and the *horizon* (the earliest time an input may change next).
``docs/clock.md`` describes the protocol of time; ``docs/protocol.md`` the bytes;
``docs/architecture.md`` the parts this class delegates to.

Every wait on the firmware has a wall-clock deadline (the watchdog); a firmware that
stops answering is stopped and reported, and :meth:`Rig.stop` always ends the
process and closes the link.
"""

import os
import time
from dataclasses import dataclass, field
from pathlib import Path

from host.artefacts.console import MAX_BYTES, ConsoleLog
from host.artefacts.folder import begin_trace_folder, drop_begun_folder, write_trace_folder
from host.artefacts.integrity import TraceWriteError, stop_signal_name
from host.artefacts.linklog import NO_LOG, LinkLog
from host.artefacts.recorder import Recorder
from host.core import paths, safefs
from host.core.errors import LinkError
from host.coverage import collector as coverage
from host.link import frames as F
from host.rig.config import arguments
from host.rig.config.budgets import BudgetHooks, ComputeBudget
from host.rig.hardware import peripherals
from host.rig.hardware.busimage import BusImages
from host.rig.hardware.bustrace import BusTrace
from host.rig.hardware.inputs import Inputs
from host.rig.hardware.outputs import Outputs
from host.rig.hardware.pio import PioHost
from host.rig.hardware.wiring import Wiring
from host.rig.loop import endings, manifest, waits
from host.rig.loop.clock import Clock, edge_segments_wanted
from host.rig.loop.messages import HANDLERS
from host.rig.loop.pacing import PACINGS
from host.rig.loop.session import Session
from host.rig.loop.spec import NO_RECORDING, Recording, RigSpec, build_plant, default_target, plant_options
from host.rig.loop.speculation import Speculation
from host.rig.scan import boards
from host.rig.targets import mcutime
from host.rig.targets.boardfs import BoardFs
from host.rig.targets.firmware import Firmware
from host.rig.targets.target import Target

PROGRESS_EVERY_S = 0.25  # wall time between two progress reports


@dataclass
class RunStats:
    link_round_trips: int = 0
    bus_round_trips: int = 0  # BUS frames answered (a bus transfer's own exchange)
    bus_local: int = 0  # bus reads the shim answered from an image (BUS_DONE: host.rig.hardware.busimage)
    irq_edges: int = 0
    edge_segments: int = 0  # encoder segments sent in EDGES (host.rig.loop.clock, edge_segments_wanted)
    rollbacks: int = 0
    lease_violations: int = 0
    round_trip_us: list = field(default_factory=list)  # STATE -> the WAIT's bytes read (Session)
    round_trip_taken_us: list = field(default_factory=list)  # STATE -> the WAIT taken, what came before it handled


def open_link_log(rig: "Rig") -> LinkLog:
    """The rig's link log (``trace.jsonl``), opened with its header: what ran, on what."""
    log = LinkLog(rig.artefacts / "trace.jsonl" if rig.artefacts else None)
    header = {
        "app": rig.app.name,
        "board": rig.board,
        "seed": rig.seed,
        "mode": rig.mode,
        "firmware": rig.firmware.identity(),
    }
    header["firmware"]["folder"] = paths.portable(header["firmware"]["folder"])  # (any checkout)
    log.write({"header": {**header, "plant": type(rig.plant).__name__}})
    return log


def firmware_and_pins(spec: RigSpec, app, board: str) -> tuple[Firmware, dict]:
    """What runs on the board (the spec's flashed folder, else the app's files for the
    board) and the board's pin map."""
    board_folder, pins = app.board_files(board)
    if spec.firmware_dir is not None:
        return Firmware.flashed(spec.firmware_dir, spec.require_main), pins
    return Firmware.from_app(app, board_folder, spec.main_dir), pins


class Rig:
    """Firmware in the loop. Use as a context manager, or call start() and stop()."""

    def __init__(
        self,
        spec: RigSpec,
        recording: Recording = NO_RECORDING,
        *,
        plant=None,
        budgets: list | None = None,
        target: Target | None = None,
    ):
        """The rig ``spec`` describes (:mod:`host.rig.loop.spec`), its plant built there unless
        given (a replay's recorded stream, a test's scripted plant); ``recording`` what the
        run keeps and shows. ``target`` is where the firmware runs (default: the unix port
        here, with the spec's link faults under its channel); ``budgets`` replace the app's
        budgets for this plant. Every failure message names the seed."""
        self.spec = spec
        self.app = spec.resolve()
        self.board = spec.board or self.app.default_board
        self.mode = spec.mode
        self.pacing = PACINGS[spec.mode]()
        self.seed = spec.seed
        self.allow_exit = spec.allow_exit or self.app.code.allow_exit
        self.watchdog_s = spec.watchdog_s
        self.firmware, pins = firmware_and_pins(spec, self.app, self.board)
        options = plant_options(spec, self.app) if plant is not None else None  # (a given plant: as built)
        self.plant, self.plant_options = (plant, options) if plant is not None else build_plant(spec, self.app)
        self.plant.reset(self.seed)
        shared = self.plant.outputs.keys() & self.plant.inputs.keys()  # (lines both drive in turn)
        self.wiring = Wiring(self.app.wiring, pins, self.board, sensors=self.plant.outputs, shared=shared)
        self.identity = self.app.board.identity or boards.identity(self.board)  # sys.platform, _machine
        self.wiring.spi_clocks = spi_clocks(self.plant) if (self.identity or ("",))[0] == "rp2" else {}
        self.recorder = Recorder(self.plant) if recording.record else None
        if budgets is None:
            budgets = self.app.make_budgets(self.plant)
        self.budgets = {b.name: b for b in budgets}
        cpu = os.environ.get("MPYFIL_CPU") or self.app.board.cpu  # (as host/rig/targets/firmware.py)
        for b in self.budgets.values():
            if isinstance(b, ComputeBudget) and cpu != "free":
                b.mcu = cpu  # the firmware's compute in the board CPU's time (docs/mcu-time.md)
        self.cpu_load = mcutime.CpuLoad(cpu) if cpu != mcutime.FREE else None
        hooks = BudgetHooks(self.budgets.values())
        self._compute_hooks = hooks.compute
        self._seen_hooks = hooks.seen
        self.bus_trace = BusTrace(hooks.bus, self.recorder, lambda: self.linklog, lambda: self.console_log)
        self.stats = RunStats()
        self.speculation = Speculation(self.plant)
        self.bus_images = BusImages(self.plant, self.wiring, self.bus_trace)
        self.bus_images.on = self.bus_images.on and self.mode == "lockstep"  # (real time: every transfer asks)
        self.inputs = Inputs(self.wiring, hooks, self.speculation, self.recorder, self.stats)
        self.outputs = Outputs(self.plant, self.wiring, hooks, self.recorder)
        self.wiring.pio = PioHost(self.plant, self.wiring, hooks.change)  # rp2.StateMachine's PIO
        self.target = target if target is not None else default_target(spec, self.app, self.pacing)
        self.artefacts = Path(recording.artefacts) if recording.artefacts else None
        self.trace_enabled = recording.trace
        self.coverage_file, self.coverage = recording.coverage, None  # (host/coverage)
        self.progress = recording.progress
        self.console_log = ConsoleLog(max_bytes=self.app.run.console_max_bytes or MAX_BYTES)
        self.micropython_version = ""
        self.exit_kind: int | None = None
        self.exit_code: int | None = None  # sys.exit's code (0 when the entry file returned)
        self.resets = 0
        self._i2ct_done = None  # (status, acks, bytes read): the last transaction on its I2CTarget (boardset.py)
        self.expect_from = 0  # console bytes before this were taken by an expect
        self.reset_watch = endings.ResetWatch()  # a reboot storm, at any rate
        self.linklog: LinkLog = NO_LOG
        self._started = False
        self.board_fs: BoardFs | None = None  # the board's flash while it runs (host/rig/targets/boardfs.py)
        self.board_fs_written: list[str] = []  # what the firmware wrote there (kept in board_fs/)
        self.board_fs_faults: list[str] = []  # files past the flash's size, not kept (host/rig/targets/boardfs.py)
        damaged = lambda error: endings.damaged(self, error)  # noqa: E731
        timed = recording.time_round_trips
        round_trips = self.stats.round_trip_us if timed else None
        taken = self.stats.round_trip_taken_us if timed else None
        self.session = Session(self._on_silence, round_trips, damaged, taken)
        parts = (self.wiring, self.inputs, self.speculation, self.recorder, self.stats, self.session)
        self.clock = Clock(self.plant, self.pacing, *parts, self.linklog)
        self.clock.images = self.bus_images
        self.clock.edge_segments = edge_segments_wanted(self.cpu_load is not None)
        self._progress_wall = 0.0
        self._progress_last = None

    # -- life cycle -------------------------------------------------------------------

    def __enter__(self):
        self.start()
        return self

    def __exit__(self, *exc):
        self.stop(interrupted=exc[1])

    @property
    def t_us(self) -> int:
        return self.plant.t_us

    @property
    def firmware_folders(self) -> list[Path]:
        return self.firmware.folders

    def start(self) -> "Rig":
        self._started = True
        try:
            if self.artefacts:  # (its parent as named; the folder itself a link: refused)
                safefs.make_folder(self.artefacts)
            self.console_log.open(self.artefacts / "console.log" if self.artefacts else None)
            if self.trace_enabled:
                self.linklog = self.clock.log = open_link_log(self)
            if self.target.board_fs:
                self.board_fs = BoardFs(self.firmware)
                self.firmware.board_root = self.board_fs.root
            coverage.start(self)
            self._open(self.target.open)
            begin_recording(self)  # (manifest.json; a header marked partial until the end)
        except BaseException:
            self._started = False  # a start that fails leaves no process and no pty, and its error stands
            self.target.close()
            end_board_fs(self)
            self.linklog.close()
            coverage.end(self, write=False)
            raise
        return self

    def _open(self, launch) -> None:
        """Start (or restart) the firmware and shake hands; what it configured before
        is forgotten, the plant carries on."""
        self.exit_kind = None
        self.wiring.clear()
        self.inputs.clear()
        self.speculation.end()
        self.clock.wait = None
        chan = launch(self.firmware, self._on_console)
        settings = self.target.shim_settings(self.firmware).packed(self.identity)
        version = self.session.handshake(chan, self.pacing.code, self.t_us, settings, self.plant.zero_delay)
        self.micropython_version = version
        self.pacing.begin(self.t_us)

    def stop(self, interrupted: BaseException | None = None) -> None:
        """End the firmware and close the link; safe to call twice. Writes the console
        and, when recording, the trace folder (:func:`finish_recording`)."""
        ended = self.exit_kind is not None or self.session.last_type == F.EXIT  # (an EXIT after a FAULT)
        self.target.close(session_open=not ended and self.session.chan is not None)
        self.plant.close()  # (a program outside serving a chip ends: sim_plant/catalogue/external.py)
        end_board_fs(self)
        self.bus_trace.flush_poll()
        if self._started:
            self._started = False
            finish_recording(self, interrupted)

    def _on_console(self, data: bytes) -> None:
        self.console_log.write(data, self.t_us)

    @property
    def console(self) -> str:
        """What the firmware printed: its last ``ConsoleLog.tail_bytes`` (all of it in
        ``artefacts/console.log``)."""
        return self.console_log.text

    @property
    def trace_digest(self) -> str | None:
        return self.linklog.digest

    # -- running --------------------------------------------------------------------

    def run_for(self, duration_s: float) -> None:
        self.run_until(self.t_us + round(arguments.seconds("run_for", duration_s, limit_s=arguments.MAX_RUN_S) * 1e6))

    def run_until(self, t_end_us, timeout_s: float | None = None):
        """Serve the firmware until virtual time reaches ``t_end_us`` (firmware waiting),
        or, given a predicate, until it is true within ``timeout_s`` simulated s (10)."""
        if callable(t_end_us):
            return waits.until(self, t_end_us, timeout_s)
        if not self.target.alive():
            raise LinkError("the rig is not running: call start() first")
        try:
            self._serve_until(t_end_us)
        finally:  # (real time: until the next run call, a pause, docs/clock.md)
            self.pacing.pause()

    def _serve_until(self, t_end_us: int) -> None:
        while True:
            if self.progress is not None:
                report_progress(self, t_end_us)
            if self.exit_kind is not None:  # firmware ended: the plant runs on alone
                self.clock.run_alone(t_end_us)
                return
            if self.clock.wait is None:
                self.to_wait()
                continue
            if self.plant.t_us >= t_end_us:  # (self.t_us)
                return
            self.clock.serve(t_end_us)

    def expect(self, pattern, timeout_s: float = 10.0):
        """Run until the console matches ``pattern`` (after what earlier expects took)."""
        return waits.expect(self, pattern, timeout_s)

    @property
    def waiting(self) -> bool:
        """The firmware waits for a STATE."""
        return self.clock.wait is not None

    def serve_wait(self, t_end_us: int) -> None:
        """Serve the pending wait, no further than ``t_end_us`` (a loop of one's own)."""
        self.clock.serve(t_end_us)

    # -- messages from the firmware ------------------------------------------------------

    def dispatch(self, type_: int, payload: bytes) -> None:
        """A message from the shim, to its handler (:mod:`host.rig.loop.messages`)."""
        handler = HANDLERS.get(type_)
        if handler is None:
            raise LinkError(f"unexpected message type 0x{type_:02x} from the shim")
        handler(self, payload)

    def to_wait(self, what: str = "a message") -> None:
        """Serve the running firmware until it blocks in a wait, or ends: each message to
        its handler, as :meth:`dispatch`. The frames a read brought are taken in this loop
        from the channel's decoder (``HostDecoder.next_plain``: a whole good frame, the one
        expected next, at the front), not each through ``Session.recv`` and
        ``Channel.recv``; the first of a read, anything else (a partial or damaged frame,
        a gap), and a WAIT whose round trip is being timed go through ``Session.recv``."""
        session, clock, handlers = self.session, self.clock, HANDLERS
        while clock.wait is None and self.exit_kind is None:
            decoder = session.chan.decoder  # (a restart's handshake may bring another channel)
            got = None
            if decoder.pos < len(decoder.buf) and not decoder.damaged:
                # (a WAIT while its round trip is timed goes through Session.recv, which times it)
                got = decoder.next_plain(F.WAIT if session._t_sent is not None else -1)
            if got is None:
                type_, payload = session.recv(self.watchdog_s, what)
            else:
                type_, _seq, payload = got
                session.last_type = type_
            handler = handlers.get(type_)
            if handler is None:
                raise LinkError(f"unexpected message type 0x{type_:02x} from the shim")
            handler(self, payload)

    def restart(self) -> None:
        """The firmware restarts on its target (a reset) and shakes hands again."""
        self.wiring.pio.reset()
        self.bus_images.forget()
        self._open(self.target.restart)

    def power_cycle(self) -> None:
        """The board loses power at this instant and boots again (a brownout): its firmware
        is stopped where it is (blocked in a wait), the lines it drove go low (a PWM stops,
        a shared line is let go) and it starts from its entry file, configuring its pins
        anew; the plant carries on. (A board among others: ``BoardSet.power_cycle``.)"""
        if self.clock.wait is None:
            raise LinkError(f"a power cycle while the firmware runs (serve it to its wait first){self.where()}")
        plant_inputs = self.outputs.plant_inputs
        for info in self.wiring.handles:
            if info.signal in plant_inputs and not info.is_input and info.kind in (F.CFG_PIN, F.CFG_PWM):
                shared = info.signal in self.wiring.shared
                self.plant.set_input(info.signal, peripherals.RELEASED if shared else 0)
        self.console_log.write(f"[power lost and back at t={self.t_us / 1e6:.6f} s]\n".encode(), self.t_us)
        self.resets += 1
        self.wiring.pio.reset()
        self.bus_images.forget()
        self._open(self.target.power_cycle)

    # -- link ------------------------------------------------------------------------

    def _on_silence(self, timeout_s: float, what: str):
        self.target.on_silence(self, timeout_s, what)

    def receive(self, timeout_s: float):
        """The next message from the shim, or None if none came within ``timeout_s``
        (for callers that serve the firmware in a loop of their own)."""
        return self.session.poll(timeout_s)

    def last_message(self) -> str:
        return self.session.last_message()

    def where(self) -> str:
        """The console's last lines, the seed and the artefacts folder, for error messages."""
        return endings.where(self)

    # -- results ---------------------------------------------------------------------

    def truth(self) -> dict:
        return self.plant.truth()

    def budget_rows(self) -> list[dict]:
        return [b.stats() for b in self.budgets.values()]

    def counters(self) -> dict:
        stats = ("link_round_trips", "irq_edges", "rollbacks", "lease_violations")
        return {**self.session.counters(), **{k.removeprefix("link_"): getattr(self.stats, k) for k in stats}}


def spi_clocks(plant) -> dict[str, str]:
    """The plant's SPI chips' clock inputs (``<name>.sck``) and their buses: consulted on an
    rp2, whose pins' functions the shim reports (elsewhere every chip hears its bus)."""
    return {d.sck_signal: d.bus for d in plant.bus_devices() if getattr(d, "sck_signal", None)}


def end_board_fs(rig) -> None:
    """Keep what the firmware wrote on its flash (``artefacts/board_fs/``); remove the copy."""
    board, rig.board_fs = rig.board_fs, None
    if board is not None:
        try:
            rig.board_fs_written = board.keep(rig.artefacts / "board_fs") if rig.artefacts else board.written()
            rig.board_fs_faults = board.faults
        finally:
            board.remove()


def report_progress(rig, t_end_us: int) -> None:
    """Tell `rig.progress` where the run is, at most every PROGRESS_EVERY_S of wall time."""
    now = time.monotonic()
    if (now >= rig._progress_wall or rig.t_us >= t_end_us) and rig._progress_last != (rig.t_us, t_end_us):
        rig._progress_wall = now + PROGRESS_EVERY_S
        rig._progress_last = (rig.t_us, t_end_us)
        rig.progress(rig.t_us, t_end_us)


def begin_recording(rig) -> None:
    """As a recorded run starts (a trace folder, or a link trace): its manifest
    (host/rig/loop/manifest.py), and the trace folder's header marked partial."""
    if rig.artefacts and (rig.recorder is not None or rig.trace_enabled):
        manifest.write(rig.artefacts, manifest.of_rig(rig))
    if rig.artefacts and rig.recorder is not None:
        begin_trace_folder(rig.artefacts, run_header(rig), rig.recorder, rig.plant)
        if rig.trace_enabled:  # (the folder's files made while the firmware works: host/artefacts/streaming.py)
            rig.linklog.idle = rig.recorder.work


def run_header(rig) -> dict:
    """The run's header for its trace folder (docs/traces.md)."""
    return {
        "app": rig.app.name,
        "rig_file": str(rig.app.rig_file) if rig.app.rig_file else None,
        "board": rig.board,
        "plant_options": dict(rig.plant_options),
        "report": rig.app.run.report.table() if rig.app.run.report is not None else None,
        "spec": rig.spec.header(rig.app),
        "seed": rig.seed,
        "mode": rig.mode,
        "micropython": rig.micropython_version.split(";")[0],
        "firmware": rig.firmware.identity(),
        "t_end_us": rig.t_us,
        **({"board_fs": rig.board_fs_written} if rig.board_fs_written else {}),
        **({"board_fs_faults": rig.board_fs_faults} if rig.board_fs_faults else {}),
        **bus_notes(rig),
        **({"mcu_time": rig.cpu_load.record(rig.t_us)} if getattr(rig, "cpu_load", None) else {}),
    }


def bus_notes(rig) -> dict:
    """For the header: the buses' notes (a poll that never ends, a chip's) and, per chip,
    the registers written that its model keeps as plain memory (register: [first t_us, writes])."""
    out = {}
    if rig.bus_trace.notes:
        out["notes"] = [{"t_us": t, "text": text} for t, text in rig.bus_trace.notes]
    devices = rig.plant.bus_devices()
    unmodelled = {
        d.label: {f"0x{r:02x}": list(v) for r, v in sorted(d.unmodelled.items())}
        for d in devices
        if getattr(d, "unmodelled", None)
    }
    if unmodelled:
        out["unmodelled_writes"] = unmodelled
    return out


def finish_recording(rig, interrupted: BaseException | None) -> None:
    """Close the console and link log and write the trace folder, marked partial when
    ``interrupted`` is a stop signal or a failed write, and the firmware's coverage when
    measured (host/coverage). A write that fails raises TraceWriteError, once (not again
    when it is what interrupted the run)."""
    try:
        _finish_trace(rig, interrupted)
    finally:
        coverage.end(rig)


def _finish_trace(rig, interrupted: BaseException | None) -> None:
    rig.linklog.close()
    rig.console_log.close(rig.t_us)
    try:
        if rig.artefacts and rig.recorder is not None:
            run = {**run_header(rig), **recording_end(rig, interrupted)}
            write_trace_folder(rig.artefacts, run, rig.recorder, rig.plant, rig.budgets)
        elif rig.artefacts:  # (a recording dropped before the end)
            drop_begun_folder(rig.artefacts)
            if not rig.trace_enabled:  # (nothing recorded stays: its manifest goes too)
                (rig.artefacts / manifest.FILE).unlink(missing_ok=True)
        error = rig.console_log.error or rig.linklog.error
        if error is not None:
            raise error
    except TraceWriteError:
        if not isinstance(interrupted, TraceWriteError):
            raise


def recording_end(rig, interrupted: BaseException | None) -> dict:
    """How the recording ended, for its header: ``stop`` (None when it ran its course),
    the streamed files cut short, and the console's counts."""
    stop = None
    # (the cut is where the firmware is known to be: a STATE it runs from, though the plant
    # looked ahead of it; what it does at that instant may have come in part)
    cut_us = rig.clock.firmware_us
    if isinstance(interrupted, KeyboardInterrupt):
        name = stop_signal_name(interrupted)
        stop = {"reason": f"stopped by {name}", "signal": name, "t_us": cut_us}
    elif isinstance(interrupted, TraceWriteError):
        reason = f"cannot write {interrupted.path.name}: {interrupted.error.strerror or interrupted.error}"
        stop = {"reason": reason, "signal": None, "t_us": cut_us}
    incomplete = {
        log.error.path.name: f"cut short: {log.error.error.strerror or log.error.error}"
        for log in (rig.console_log, rig.linklog)
        if log.error is not None
    }
    return {"stop": stop, "incomplete": incomplete, "console": rig.console_log.summary}
