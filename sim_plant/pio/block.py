"""One PIO block in virtual time: instruction memory, IRQ flags, the GPIO levels its state
machines read, the levels they drive (with their instants), run forward over a timeline
of input changes.

Time: a state machine started at ``t0_us`` runs its cycle ``c`` at
``t0_us + c / freq`` (which cycle a time falls on is integer arithmetic); a pin change at ``t_us`` is seen
from the first cycle at or after it. Between two changes the pins are constant, and a
state machine that comes back to a state it was in (its registers, FIFOs, program counter
and the block's IRQ flags: :meth:`StateMachine.key`) repeats the same stretch for ever:
:func:`run_cycles` skips every whole period at once, replaying what the period drives.
A ``wait`` on a pin, a blocked FIFO, a polling loop (a quadrature decoder between edges)
costs a few steps per input change, whatever the time between changes.
"""

import copy

from sim_plant.pio.machine import PioConfig, StateMachine

SEEN_MAX = 4096  # loop heads remembered in one constant stretch before starting afresh


class Running:
    """A state machine's clock: started at ``t0_us``, ``cycle`` cycles run since."""

    def __init__(self, sm: StateMachine, t0_us: int):
        self.sm = sm
        self.t0_us = t0_us
        self.cycle = 0
        self.active = False
        self.orbit = 0  # the period (cycles) of the loop it is in, drives nothing: 0 unknown
        self.orbit_version = -1  # ... as long as the block's version is this one
        self.drive_period = 0  # the period (cycles) of the last loop found that drives pins

    def cycle_at(self, t_us: int) -> int:
        """The first cycle at or after ``t_us`` (exact: cycles per µs = SYS_HZ*256 / (div256 * 10**6))."""
        num = (t_us - self.t0_us) * self.sm.config.SYS_HZ * 256
        return -((-num) // (self.sm.config.div256 * 1_000_000))

    def time_us(self, cycle: int) -> float:
        return self.t0_us + cycle * self.sm.config.div256 * 1_000_000 / (self.sm.config.SYS_HZ * 256)


class PioBlock:
    """PIO0 or PIO1: up to four state machines sharing memory, IRQ flags and GPIOs."""

    def __init__(self, block_id: int = 0):
        self.block_id = block_id
        self.memory = [0] * 32
        self.irq_flags = 0
        self.gpio_in = 0
        self.levels: dict[int, int] = {}  # gpio -> the level a state machine drives
        self.dirs: dict[int, int] = {}  # gpio -> 1 output, 0 input (pindirs)
        self.events: list[tuple] = []  # (t_us float, gpio, level): driven changes, in time order
        self.irqs: list[tuple] = []  # (t_us float, flag, sm_id): flags 0..3 raised (the CPU's IRQ)
        self.running: dict[int, Running] = {}
        self.steps = 0  # instructions stepped (the cost)
        self.version = 0  # bumped by every change from outside: a pin, a FIFO access, an exec
        self._run: Running | None = None  # (the state machine stepping: the instant of a drive)
        self._now_us = 0.0
        self._log: list | None = None  # (cycle, call, args): what the stretch watched for a period did
        self._cycle = 0

    # -- configuration ---------------------------------------------------------------
    def load(self, memory: list[int]) -> None:
        self.memory = list(memory) + [0] * (32 - len(memory))

    def init(self, sm_id: int, config: PioConfig, t_us: int) -> StateMachine:
        old = self.running.get(sm_id)
        sm = StateMachine(self, sm_id, config)
        if old is not None:
            sm.tx, sm.rx = old.sm.tx, old.sm.rx
        self.running[sm_id] = Running(sm, t_us)
        return sm

    def sm(self, sm_id: int) -> StateMachine:
        return self.running[sm_id].sm

    def set_active(self, sm_id: int, active: bool, t_us: int) -> None:
        run = self.running[sm_id]
        if active and not run.active:
            run.t0_us, run.cycle = t_us, 0
        run.active = active

    # -- what the state machines do to the world -------------------------------------------
    def now_us(self) -> float:
        run = self._run
        return run.time_us(self._cycle) if run is not None else self._now_us

    def touch(self) -> None:
        """Something outside the state machines changed what they may do next."""
        self.version += 1

    def drive(self, gpio: int, level: int, dirs: bool = False) -> None:
        if self._log is not None:
            self._log.append((self._cycle, self.drive, (gpio, level, dirs)))
        if dirs:
            self.dirs[gpio] = level
            return
        if self.levels.get(gpio) != level:
            self.levels[gpio] = level
            self.events.append((self.now_us(), gpio, level))

    def raise_irq(self, flag: int, sm_id: int) -> None:
        if self._log is not None:
            self._log.append((self._cycle, self.raise_irq, (flag, sm_id)))
        self.irq_flags |= 1 << flag
        if flag < 4:
            self.irqs.append((self.now_us(), flag, sm_id))

    def set_input(self, gpio: int, level: int) -> None:
        self.version += 1
        if level:
            self.gpio_in |= 1 << gpio
        else:
            self.gpio_in &= ~(1 << gpio)

    # -- time --------------------------------------------------------------------------
    def advance(self, t_us: int, changes=()) -> None:
        """Run every active state machine to ``t_us`` (not its cycle at ``t_us``), the pin
        changes ``(t_us, gpio, level)`` (in time order, none after ``t_us``) applied as
        they come."""
        for t_change, gpio, level in changes:
            self._run_all(t_change)
            self.set_input(gpio, level)
        self._run_all(t_us)

    def _run_all(self, t_us: int) -> None:
        for run in self.running.values():
            if run.active:
                run_cycles(self, run, run.cycle_at(t_us))

    def probe(self, sm_id: int, t_us: int, horizon_us: int, want) -> float | None:
        """When ``want(sm)`` first holds if the pins stay as they are, looking no further
        than ``horizon_us`` (None: not by then); the block itself is not moved."""
        twin = copy.deepcopy(self)
        run = twin.running[sm_id]
        step_us = 1
        t = t_us
        while t < t_us + horizon_us:
            t = min(t_us + horizon_us, t + step_us)
            twin._run_all(t)
            if want(run.sm):
                return t
            step_us *= 2
        return None


def run_cycles(block: PioBlock, run: Running, c_end: int) -> None:
    """Step ``run``'s state machine up to (not including) cycle ``c_end``, pins constant,
    skipping whole periods of a loop it has come back to (one known from before, while
    nothing changed, is skipped at once)."""
    sm = run.sm
    c = run.cycle
    if run.orbit and run.orbit_version == block.version and c < c_end:
        c += (c_end - c) // run.orbit * run.orbit
    seen: dict = {}
    block._log = log = []
    block._run = run
    step = sm.step
    try:
        while c < c_end:
            pc = sm.pc
            block._cycle = c
            c += step()
            block.steps += 1
            if sm.pc > pc:
                continue
            key = sm.key()
            first = seen.get(key)
            if first is None:
                if len(seen) >= SEEN_MAX:
                    seen.clear()
                    log.clear()
                seen[key] = (c, len(log))
                continue
            period = c - first[0]
            if len(log) == first[1]:  # (a loop that drives nothing: remembered until something changes)
                run.orbit, run.orbit_version = period, block.version
            else:
                run.drive_period = period
            c = _skip_periods(block, run, first, c, c_end, log)
            seen.clear()
            log.clear()
    finally:
        block._log = None
        block._run = None
    run.cycle = c


def _skip_periods(block, run, first, c, c_end, log) -> int:
    """``sm`` is at cycle ``c`` in the state it had at ``first[0]``: jump over the whole
    periods that fit before ``c_end``, replaying the period's drives for each."""
    c_first, i_first = first
    period = c - c_first
    periods = (c_end - c) // period
    if periods <= 0:
        return c
    pattern = log[i_first:]
    block._log = None
    try:
        for k in range(1, periods + 1) if pattern else ():
            for cycle, call, args in pattern:
                block._cycle = cycle + k * period
                call(*args)
    finally:
        block._log = log
    return c + periods * period
