"""Several boards in one lockstep (``docs/multi-board.md``): each board's firmware its own
interpreter on its own pty (a :class:`~host.rig.loop.rig.Rig` each, on a
:class:`~host.rig.loop.boardview.BoardView` of the one plant), one virtual clock.

The set serves in rounds. At the start of a round every board is blocked in a wait. The
round's instant is the earliest at which a board can wake: the earliest end of a board's
wait, a ground-truth sample, the run's end, and the plant's next change (which holds the
bytes and levels in flight on the wires between boards) when it can end a board's wait
(:func:`wakeable`). The plant is brought to that instant, its changes queued for the
boards wired to them; each board with something there is served in the boards' order,
and one whose wait ends (its time, an IRQ edge, a watched input) gets its STATE. Its horizon is the
plant's next change or the earliest instant another board could act, at least the µs
after the instant, so the board moves its clock no further without asking. Then each
woken board is served, in order, until it blocks again: what it writes goes into the plant
at its instant, and so, through a wire, to another board's inputs, at once or after the
wire's delay (a UART byte: its 10 bits at the sender's baud rate). Since nothing is read
from the boards but in that fixed order, the same seed gives the same traces byte for
byte, however the processes are scheduled.
"""

import contextlib
import struct
from pathlib import Path

from host.artefacts.folder import GTKW, VCD
from host.artefacts.integrity import TraceWriteError
from host.artefacts.vcd import merge_vcd, write_set_gtkw
from host.core.errors import ConfigError, HarnessError, LinkError
from host.link import frames as F
from host.rig.config import arguments
from host.rig.config.boardfile import ProgramSpec
from host.rig.config.budgets import ReactionBudget
from host.rig.hardware.peripherals import TARGET_PREFIX
from host.rig.loop.boardview import BoardView, couple
from host.rig.loop.hostboard import HostProgram, load_program
from host.rig.loop.rig import Rig
from host.rig.loop.spec import Recording, RigSpec
from sim_plant.buses import FIRST_ADDRESS, LAST_ADDRESS
from sim_plant.faults import HARNESS_KINDS, FaultError, parse_faults, with_faults
from sim_plant.plant import check_contract

MAX_ROUNDS_AT_ONE_INSTANT = 100_000
"""Rounds at one instant before the set calls it a loop in zero time (two boards answering
each other's edges at the same µs, for ever)."""


def _world_of(app, world: str) -> dict:
    if world not in app.worlds:
        raise ConfigError(f"world: unknown world {world!r} (the file's worlds: {', '.join(app.worlds)})")
    return app.worlds[world]


def split_faults(boards, faults) -> tuple[list, dict]:
    """A set's fault tables (a campaign's fault set): those of the harness (``link_corrupt``,
    ``link_stall``, ``brownout``, ``heap``) name their board (``board = "motor"``) and go
    to that board's rig; the others act on the one plant and name none. Returns (the
    plant's tables, board -> its tables); a mistake is a ConfigError naming the table."""
    plant, own = [], {}
    for i, entry in enumerate(faults or ()):
        table = dict(entry) if isinstance(entry, dict) else entry
        board = table.pop("board", None) if isinstance(table, dict) else None
        kind = table.get("kind") if isinstance(table, dict) else None
        if kind in HARNESS_KINDS:
            if board not in boards.firmware():
                known = ", ".join(boards.firmware())
                raise ConfigError(f"faults[{i}] ({kind}) board: expected the board it acts on ({known}), got {board!r}")
            own.setdefault(board, []).append(table)
        elif board is not None:
            raise ConfigError(f"faults[{i}] ({kind}) board: a fault of the one plant names no board")
        else:
            plant.append(table)
    try:  # (each board's, and the plant's, checked as one schedule: FaultError names the field)
        for entries in (plant, *own.values()):
            parse_faults(entries)
    except FaultError as e:
        raise ConfigError(str(e)) from None
    return plant, own


def label_error(error: HarnessError, board: str) -> None:
    """``error``'s message names ``board`` first (once)."""
    if board and error.args and isinstance(error.args[0], str) and not error.args[0].startswith("board "):
        error.args = (f"board {board}: {error.args[0]}", *error.args[1:])


def truth_due(rig: Rig, t_us: int) -> bool:
    return rig.recorder is not None and rig.recorder.next_truth_us <= t_us


def wakeable(rig) -> bool:
    """Whether an input change could end ``rig``'s wait before its end: its wait watches an
    input, or an IRQ is armed on one of its pins (or it is not blocked). Another board's wait
    that no change can end needs no round at each change of the plant: only at its end."""
    wait = rig.clock.wait
    return wait is None or bool(wait.watch) or getattr(rig.wiring, "irq_armed", False)


def settle(rigs: dict, serving: list) -> None:
    """Serve each board of ``rigs`` that is running, in order, until it blocks (or ends),
    its name in ``serving[0]``."""
    for board, rig in rigs.items():
        if rig.clock.wait is None and rig.exit_kind is None:  # (to_wait's own test: no call where it has none)
            serving[0] = board
            rig.to_wait()


def routes_of(views: dict) -> dict:
    """Each signal some board is wired to -> those boards' queues, in the boards' order."""
    routes: dict = {}
    for view in views.values():
        for signal in view.signals:
            routes.setdefault(signal, []).append(view.queue)
    return {signal: tuple(queues) for signal, queues in routes.items()}


@contextlib.contextmanager
def naming(board: str):
    """Any harness error raised while serving ``board`` names it first."""
    try:
        yield
    except HarnessError as e:
        label_error(e, board)
        raise


def merge_vcds(boards) -> HarnessError | None:
    """A recorded set's ``artefacts/trace.vcd``: each board's ``trace.vcd`` a scope of its
    own; and its GTKWave save file, ``trace.gtkw`` (a group a board). The error, if it could
    not be written (each board's own stands)."""
    parts = {name: boards.artefacts / name / VCD for name, rig in boards.rigs.items() if isinstance(rig, Rig)}
    parts = {name: path for name, path in parts.items() if path.is_file()}
    if not parts:
        return None
    comment = f"boards {', '.join(parts)} of {boards.spec.name} seed {boards.seed} (each board's own VCD in its folder)"
    try:
        declared = merge_vcd(boards.artefacts / VCD, parts, top=boards.spec.name, comment=comment)
        write_set_gtkw(boards.artefacts / GTKW, VCD, declared)
    except (OSError, ValueError) as e:  # (a full disk, a board's VCD cut short)
        return TraceWriteError(f"the set's trace.vcd in {boards.artefacts} was not written: {e}")
    return None


class BoardSet:
    """Boards of a rig file with ``[[boards]]`` (:func:`host.rig.config.boardfile.load_boards`)
    on one plant and one clock. Use as a context manager, or call start() and stop()."""

    def __init__(
        self,
        boards,
        seed: int = 0,
        *,
        artefacts=None,
        trace=False,
        record=False,
        watchdog_s=5.0,
        coverage=None,
        world: str | None = None,
        plant_options: dict | None = None,
        faults: list | None = None,
        allow_exit: bool = False,
    ):
        """``boards``: a :class:`~host.rig.config.boardfile.Boards` (the apps by board name and
        the plant's builder); ``artefacts``: the folder under which each board's trace
        folder is made, named as the board; ``coverage``: a board's name -> the coverage.py
        data file its firmware's coverage goes to (docs/coverage.md), or None; ``world``: one
        of the file's ``[worlds.<name>]``, and ``plant_options`` over it (as ``--param``);
        ``faults``: fault tables (:func:`split_faults`: the harness's name their board), the
        brown-outs' instants in ``brownouts`` for the caller to cut (:meth:`power_cycle`);
        ``allow_exit``: a board's firmware may end (the others carry on), else its end fails
        the run, naming it."""
        self.spec = boards
        self.seed = arguments.seed(seed)
        first = next(a for a in boards.apps.values() if not isinstance(a, ProgramSpec))
        options = dict(_world_of(first, world)) if world else {}
        options.update(plant_options or {})
        try:
            made = boards.make_plant(**options)
        except (TypeError, ValueError, ArithmeticError) as e:
            raise ConfigError(f"{boards.name}: the plant rejects {options}: {e}") from None
        plant_faults, board_faults = split_faults(boards, faults)
        try:
            self.plant = with_faults(check_contract(made), parse_faults(plant_faults))
        except FaultError as e:
            raise ConfigError(f"{boards.name}: {e}") from None
        self.plant.reset(self.seed)
        self.brownouts = sorted(  # (t_us, board): the brown-outs the faults schedule
            (round(f.at_s * 1e6), board)
            for board, entries in board_faults.items()
            for f in parse_faults(entries)
            if f.kind == "brownout"
        )
        self.artefacts = Path(artefacts) if artefacts else None
        self.recorded = bool(record)  # (each board records its signals: their VCDs merged at the stop)
        self.rigs: dict[str, Rig] = {}
        self.views: dict[str, BoardView] = {}
        for name, app in boards.apps.items():
            view = BoardView(self, name)
            if isinstance(app, ProgramSpec):  # a host program standing in for a board
                folder = self.artefacts / name if self.artefacts else None
                with naming(name):
                    program = HostProgram(name, load_program(app.path, app.function), view, folder, watchdog_s)
                self.rigs[name], self.views[name] = program, view
                continue
            own = {"faults": tuple(board_faults.get(name, ())), "allow_exit": allow_exit}
            spec = RigSpec(app=app, seed=self.seed, watchdog_s=watchdog_s, busy_poll=False, **own)
            folder = self.artefacts / name if self.artefacts else None
            measured = coverage(name) if coverage is not None else None
            with naming(name):
                rig = Rig(spec, Recording(trace=trace, record=record, artefacts=folder, coverage=measured), plant=view)
            couple(rig)
            view.signals = rig.wiring.wired
            self.rigs[name], self.views[name] = rig, view
        self.routes: dict | None = None  # a plant signal -> the queues of the boards wired to it (made when needed)
        self.plant_clear_us = -1  # the plant is at least there with nothing due by then, nothing written since
        self._instant = (-1, 0)  # (the last round's instant, rounds at it)
        self.rounds = 0  # rounds served (a round: the plant to an instant, each board with something there served)
        self.i2c_links = dict(boards.i2c_links)  # (controller, bus) -> target board: board_i2c parts
        self.budgets: dict[str, ReactionBudget] = {}  # the budgets across boards (the file's [budgets])
        for name, (stimulus, response, limit_us, description) in boards.budgets.items():
            budget = ReactionBudget(name, stimulus, response, limit_us=limit_us, description=description)
            for (board, signal), call in ((stimulus, budget.on_stimulus), (response, budget.on_response)):
                self.rigs[board].outputs.level_hooks.setdefault(signal, []).append(call)
            self.budgets[name] = budget
        self._in_target = None  # the target board a controller's transfer is being served by

    # -- life cycle ---------------------------------------------------------------------

    def __enter__(self):
        self.start()
        return self

    def __exit__(self, *exc):
        self.stop(interrupted=exc[1])

    def start(self) -> "BoardSet":
        try:
            for name, rig in self.rigs.items():
                with naming(name):
                    rig.start()
        except BaseException:
            self.stop()
            raise
        return self

    def stop(self, interrupted: BaseException | None = None) -> None:
        """Stop every board (each writes its console and trace); the first error stands.
        Recorded, the boards' VCDs are merged into the artefacts' own ``trace.vcd``, one
        scope per board."""
        error = None
        for name, rig in self.rigs.items():
            try:
                with naming(name):
                    rig.stop(interrupted)
            except HarnessError as e:
                error = error or e
        if self.artefacts is not None and self.recorded:
            error = error or merge_vcds(self)
        if error is not None and interrupted is None:
            raise error

    def __getitem__(self, name: str) -> Rig:
        return self.rigs[name]

    @property
    def t_us(self) -> int:
        return self.plant.t_us

    def truth(self) -> dict:
        return self.plant.truth()

    # -- running ------------------------------------------------------------------------

    def run_for(self, duration_s: float) -> None:
        seconds = arguments.seconds("run_for", duration_s, limit_s=arguments.MAX_RUN_S)
        self.run_until(self.t_us + round(seconds * 1e6))

    def run_until(self, t_end_us: int) -> None:
        """Serve every board until virtual time reaches ``t_end_us``, all of them blocked."""
        serving = [""]  # (the board being served, for an error's message)
        try:
            self._serve_until(t_end_us, serving)
        except HarnessError as e:
            label_error(e, serving[0])
            raise
        for budget in self.budgets.values():
            budget.end(self.t_us)

    def _serve_until(self, t_end_us: int, serving: list) -> None:
        rigs, views = self.rigs, self.views
        self.plant_clear_us = -1  # (the plant may have been moved between runs: a scenario's carry_to)
        while True:
            settle(rigs, serving)
            t_us = self._next_instant(t_end_us)
            if t_us is None:
                return
            serving[0] = ""
            self.plant_to(t_us)
            for board, rig in rigs.items():
                view = views[board]
                serving[0] = board
                if rig.exit_kind is not None:  # (a board that ended: its inputs go nowhere)
                    view.queue.clear()
                    view.advance_to(t_us)
                elif view.queue or rig.clock.wait.t_until <= t_us or t_us >= t_end_us or truth_due(rig, t_us):
                    rig.clock.bound_us = self._others_act_us(board, t_us, t_end_us)
                    rig.clock.serve(t_us)  # (a board with nothing at this instant waits for its next)

    def _others_act_us(self, board: str, t_us: int, t_end_us: int) -> int:
        """The earliest instant a board other than ``board`` could act, with nothing written
        meanwhile: the µs after ``t_us`` if one may wake at it (its wait ends, a change waits
        for it), else the earliest end of their waits (or a truth sample one records); never
        past the run's end. (The plant's
        own next change bounds the horizon besides: ``BoardView.next_change_us``.)"""
        earliest = t_end_us
        for other, rig in self.rigs.items():
            if other == board or rig.exit_kind is not None:
                continue
            wait = rig.clock.wait
            if wait is None or wait.t_until <= t_us or (self.views[other].queue and wakeable(rig)):
                return t_us + 1
            earliest = min(earliest, wait.t_until)
            if rig.recorder is not None:  # (its truth sample: the shared plant must be there then)
                earliest = min(earliest, rig.recorder.next_truth_us)
        return earliest

    def _next_instant(self, t_end_us: int) -> int | None:
        """The round's instant: the earliest at which anything may change; None when every
        board is at ``t_end_us`` with nothing left at that instant."""
        plant, views = self.plant, self.views
        t_us = t_end_us
        woken = behind = queued = False  # a live board a change can wake; one short of the end; a change queued
        for name, rig in self.rigs.items():
            view = views[name]
            live = rig.exit_kind is None
            can_wake = live and wakeable(rig)
            woken = woken or can_wake
            if view.queue:
                queued = True
                if can_wake or not live:
                    t_us = min(t_us, view.queue[0][0])
            if live:
                t_us = min(t_us, rig.clock.wait.t_until)
                if rig.recorder is not None:
                    t_us = min(t_us, rig.recorder.next_truth_us)
            behind = behind or view.t_us < t_end_us
        if woken:
            t_us = min(t_us, plant.next_change_us())
        t_us = max(t_us, plant.t_us)
        if t_us >= t_end_us and not behind and not queued:
            return None
        t_us = min(t_us, t_end_us)
        self.rounds += 1
        last, rounds = self._instant
        self._instant = (t_us, rounds + 1 if t_us == last else 0)
        if rounds > MAX_ROUNDS_AT_ONE_INSTANT:
            raise LinkError(
                f"the boards went {rounds} rounds at virtual t={t_us / 1e6:.6f} s without time moving "
                f"(boards answering each other at the same instant for ever?); seed: {self.seed}"
                + (f"; artefacts: {self.artefacts}" if self.artefacts else "")
            )
        return t_us

    def to_target(self, board: str, bus: str, op: int, address: int, n_read: int, data: bytes) -> tuple | None:
        """A transfer of ``board``'s on ``bus`` to the board its ``board_i2c`` part names, if
        that board's firmware is a ``machine.I2CTarget`` at ``address`` (else None: the
        plant's chips answer it): the target, blocked at or before this instant, gets the
        transaction at it (a change that ends its wait, as an interrupt), runs its state
        machine and its handlers there, and is served until it blocks again; then its
        answer (status, acks, the bytes read) is the controller's. Both boards' horizons
        are then the µs after: either may act at once on what the other did."""
        target = self.i2c_links.get((board, bus))
        if target is None or op not in (F.BUS_XFER, F.BUS_XFER_NOSTOP):
            return None
        rig = self.rigs[target]
        if self._in_target is not None:
            raise LinkError(
                f"board {board} addressed board {target}'s I2C target while board {self._in_target} was "
                f"answering one at the same instant (boards that are each other's targets at once are not modelled)"
            )
        t_us = self.views[board].t_us
        self._in_target = target
        try:
            with naming(target):
                rig.to_wait()  # (running: to its wait first)
                h = rig.wiring.i2c_targets.get(address) if rig.exit_kind is None else None
                if h is None:  # (no target there: the plant's chips answer)
                    return None
                view = self.views[target]
                if view.t_us > t_us:
                    raise LinkError(
                        f"board {target} is at t={view.t_us} us, past board {board}'s transfer at {t_us} us "
                        f"(the set of boards lost lockstep)"
                    )
                xact = struct.pack(F.I2CT_XACT_FMT, op, n_read) + bytes(data)
                view.queue.append((t_us, TARGET_PREFIX + rig.wiring.handles[h].key, xact))
                rig._i2ct_done = None
                rig.clock.bound_us = t_us + 1
                rig.clock.serve(t_us)
                rig.to_wait("the target's answer")
        finally:
            self._in_target = None
        self.rigs[board].clock.bound_us = t_us + 1
        if rig._i2ct_done is None:
            return None if rig.exit_kind is not None else (F.BUS_NACK_ADDRESS, 0, b"")
        return rig._i2ct_done

    def power_cycle(self, board: str) -> None:
        """Board ``board`` loses power at the set's instant and boots again (a brownout:
        ``Rig.power_cycle``), every board blocked in its wait; the others and the plant
        carry on. A host program has no power to lose (it is refused)."""
        rig = self.rigs[board]
        if not isinstance(rig, Rig):
            raise ConfigError(f"board {board} is a host program: it has no power to lose")
        serving = [""]
        settle(self.rigs, serving)
        with naming(board):
            rig.power_cycle()
            rig.to_wait()  # (its boot, to its first wait)

    def target_addresses(self, board: str, bus: str) -> set:
        """The addresses another board's I2CTarget has taken on ``board``'s ``bus`` (a scan's),
        that board brought to its wait first."""
        target = self.i2c_links.get((board, bus))
        rig = self.rigs[target] if target is not None and self._in_target is None else None
        if rig is not None:
            with naming(target):
                rig.to_wait()
        if rig is None or rig.exit_kind is not None:
            return set()
        return {a for a in rig.wiring.i2c_targets if FIRST_ADDRESS <= a <= LAST_ADDRESS}

    def plant_to(self, t_us: int, view: BoardView | None = None) -> None:
        """Bring the shared plant to ``t_us`` (a board's view asks), its changes queued for
        every board wired to their signals."""
        if t_us <= self.plant_clear_us:  # (brought there already this round, nothing written since)
            return
        plant = self.plant
        self.plant_clear_us = t_us  # (nothing is due by then once advanced; a board's write clears it)
        if plant.t_us >= t_us and plant.next_change_us() > t_us:
            return
        changes = plant.advance_to(t_us)
        if changes:
            routes = self.routes
            if routes is None:
                routes = self.routes = routes_of(self.views)
            for change in changes:
                for queue in routes.get(change[1], ()):
                    queue.append(change)
