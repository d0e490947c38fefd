"""One board's side of a rig with several boards (``docs/multi-board.md``): its view of
the one shared plant, the clock that serves it, and the pacing it runs under.

Every board is a :class:`~host.rig.loop.rig.Rig` of its own (its interpreter, pty, wiring,
budgets, console and trace), given a :class:`BoardView` as its plant. The view takes its
changes from the shared plant as :class:`~host.rig.loop.boardset.BoardSet` advances it (only
the signals the board's pins are wired to), and passes the board's outputs on to it, so
that to each board another board's output is plant input like any other.

No board speculates (:class:`Coupled`): the shared plant cannot be rewound for one board
while another has already acted on it, so an IRQ edge ends a board's wait at its instant
(:class:`BoardClock`), and the set never moves the plant past an instant any board could
still act at.
"""

from collections import deque

from host.core.errors import ConfigError, LinkError
from host.link import frames as F
from host.rig.loop.clock import Clock
from host.rig.loop.pacing import Lockstep
from sim_plant.plant import NEVER_US


class Coupled(Lockstep):
    """Lockstep for a board among others: no speculation, no lookahead, an IRQ edge ends
    the batch (the board's next output may change another board's inputs at once)."""

    name = "coupled"
    speculates = False
    irq_ends_batch = True


class BoardView:
    """The shared plant as one board sees it: its changes for this board's signals, queued
    by the set until the board's clock takes them; writes passed through at the plant's
    instant. Anything else a plant answers (truth, world, buses, parts) is the shared
    plant's."""

    def __init__(self, boards, name: str):
        self._boards = boards  # host.rig.loop.boardset.BoardSet: it advances the shared plant
        self._core = boards.plant
        self.board_name = name
        self._signals: frozenset = frozenset()  # the signals this board's pins are wired to (set once wired)
        self.queue: deque = deque()  # changes of the shared plant not yet taken by this board
        self.t_us = self._core.t_us  # (where this board has taken the plant to: an attribute, read often)
        self.inputs = self._core.inputs
        self.outputs = self._core.outputs
        self.zero_delay = self._core.zero_delay

    def __getattr__(self, name):  # (truth, world, bus_devices, describe, capabilities, ...)
        self._boards.plant_clear_us = -1  # (what is asked of the shared plant may change it: looked at again)
        return getattr(self._core, name)

    @property
    def signals(self) -> frozenset:
        return self._signals

    @signals.setter
    def signals(self, signals) -> None:
        self._signals = frozenset(signals)
        self._boards.routes = None  # (the set's signal -> queues, made again when next needed)

    def wired_signals(self) -> list | None:
        """The signals this board's pins are wired to, for its trace header: the report draws
        a board's readings and commands of those alone, the shared ground truth of every part
        (host/report/part_views.py)."""
        return sorted(self.signals)

    edge_counters = ()
    """(Not the shared plant's: a board's edges come through its queue, one change each.)"""

    def advance_edges(self, t_us: int, limit: int, segs: list, seg_room: int = 0) -> list:
        return self.advance_to(t_us, limit)

    def reset(self, seed: int) -> None:
        """(The set resets the shared plant, once.)"""

    def advance_to(self, t_us: int, limit: int = 0) -> list:
        """This board's changes up to ``t_us`` (those at the current instant too: another
        board's write that arrives now); at most ``limit`` instants' worth past ``limit``."""
        self._boards.plant_to(t_us, self)
        queue = self.queue
        if not queue or (queue[-1][0] <= t_us and (not limit or len(queue) <= limit)):  # (all of it)
            taken = list(queue)
            queue.clear()
            if t_us > self.t_us:
                self.t_us = t_us
            return taken
        taken = []
        while queue and queue[0][0] <= t_us:
            if limit and len(taken) >= limit and queue[0][0] > taken[-1][0]:
                self.t_us = taken[-1][0]
                return taken
            taken.append(queue.popleft())
        self.t_us = max(self.t_us, t_us)
        return taken

    def next_change_us(self) -> int:
        return min(self.queue[0][0] if self.queue else NEVER_US, self._core.next_change_us())

    def _at_plant(self) -> None:
        """A write at this board's instant: the shared plant must be there (never past it)."""
        if self._core.t_us > self.t_us:
            raise LinkError(
                f"board {self.board_name} wrote at t={self.t_us} us, before the shared plant's "
                f"{self._core.t_us} us (the set of boards lost lockstep)"
            )
        boards = self._boards
        boards.plant_to(self.t_us, self)
        boards.plant_clear_us = -1  # (the write that follows may make a change due at once)

    def set_input(self, name: str, value) -> None:
        self._at_plant()
        self._core.set_input(name, value)

    def set_pwm(self, name: str, freq_hz: int, duty_u16: int) -> None:
        self._at_plant()
        self._core.set_pwm(name, freq_hz, duty_u16)

    def send_bytes(self, name: str, data: bytes, baud: int) -> None:
        self._at_plant()
        self._core.send_bytes(name, data, baud)

    def bus_transfer(self, bus: str, op: int, address: int, n_read: int, data: bytes, **kwargs):
        """A transfer on this board's ``bus``: to another board's I2CTarget if a ``board_i2c``
        wires them and that board has taken ``address`` (:meth:`BoardSet.to_target`), else to
        the shared plant's chips."""
        self._at_plant()
        routed = self._boards.to_target(self.board_name, bus, op, address, n_read, data)
        if routed is not None:
            return routed
        status, count, got = self._core.bus_transfer(bus, op, address, n_read, data, **kwargs)
        if op == F.BUS_SCAN and status == F.BUS_OK:  # (the target boards' addresses answer a scan too)
            found = sorted(set(got) | self._boards.target_addresses(self.board_name, bus))
            return status, len(found), bytes(found)
        return status, count, got

    def output(self, name: str):
        return self._core.output(name)

    def snapshot(self):
        raise LinkError(f"board {self.board_name}: a board among others never speculates (nothing to snapshot)")

    def restore(self, snap) -> None:
        raise LinkError(f"board {self.board_name}: a board among others never rewinds the shared plant")


class BoardClock(Clock):
    """The clock of a board among others: the plant advanced for its wait up to the instant
    the set serves, taking the changes that arrived at the current instant first (another
    board's write at the same µs), and the wait ended at any IRQ edge or watched change."""

    def advance(self, target_us: int, watch: frozenset) -> bool:
        plant, inputs, recorder = self.plant, self.inputs, self.recorder
        while True:
            changes = plant.advance_to(target_us if recorder is None else self.to_truth(target_us), inputs.room())
            irq = hit = False
            if changes:
                irq, hit = inputs.route_all(changes, watch)
            if recorder is not None:
                recorder.sample(plant)
            if irq or hit or inputs.full():
                return True
            if plant.t_us >= target_us:
                return False

    def catch_up(self, t_us: int) -> None:
        """(At the plant's instant, the usual case: only the commit, without its calls when
        nothing waits for it. A board among others never rewinds.)"""
        if t_us != self.plant.t_us:
            super().catch_up(t_us)
            return
        if self.speculation.deferred:
            self.speculation.commit(t_us)
        if self.recorder is not None:
            self.recorder.commit(t_us)

    bound_us = 0
    """The earliest instant another board could act (the set's, before each round's serve):
    with no write of its own, nothing changes this board's inputs before it."""

    def _send_state(self, base_us: int, t_end_us: int, t_us: int) -> None:
        """The STATE at the set's instant ``t_end_us``; its horizon the plant's next change or
        the instant another board could act (``bound_us``), at least the µs after this one:
        another board's write at this same instant comes in the next STATE, as if written
        just after this board's reads. A write of its own voids the horizon (the shim's)."""
        super()._send_state(base_us, max(t_end_us + 1, self.bound_us), t_us)

    def lease_us(self) -> int:
        """(After a bus transfer: as a STATE's horizon.)"""
        return min(self.plant.next_change_us(), max(self.end_us + 1, self.bound_us, self.plant.t_us))


def couple(rig) -> None:
    """Make ``rig`` (built on a :class:`BoardView`, not yet started) a board among others:
    the coupled pacing and a :class:`BoardClock` in place of its own."""
    rig.pacing = Coupled()
    parts = (rig.wiring, rig.inputs, rig.speculation, rig.recorder, rig.stats, rig.session)
    rig.clock = BoardClock(rig.plant, rig.pacing, *parts, rig.linklog)
    rig.clock.images = rig.bus_images
    rig.run_until = lambda *args, **kwargs: _alone(rig.plant.board_name)  # (run_for, expect: through it)


def _alone(board: str):
    raise ConfigError(
        f"board {board} is one of a set of boards: run the set (its run_for, run_until), which serves "
        f"every board on one clock, not one board alone (docs/multi-board.md)"
    )
