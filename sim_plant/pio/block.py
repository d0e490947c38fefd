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
from collections import deque

from sim_plant.pio import trace, walk
from sim_plant.pio.machine import PioConfig, StateMachine, read_mask, relative

SEEN_MAX = 4096  # loop heads remembered in one constant stretch before starting afresh
COUNTDOWN = True  # jump over a counting loop's passes that do the same (False: step each, for tests)
PASS_MAX = 64  # the longest pass of a counting loop looked at (instructions)
SHORT_CYCLES = 64  # a stretch shorter than this after a change is stepped, not run with symbols
AHEAD_CYCLES = 512  # how far a stretch is run with symbols past the instant asked for, to reach its loop
AHEAD_MISSES = 16  # runs past the instant that found no loop fit for the table before a state machine stops


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
        self.entries: dict = {}  # shape -> [trace.Entry]: stretches after a change, replayed
        self.unaliased: set = set()  # shapes whose shift register only matched X or Y by chance
        self.table = None  # (entry, x, y, rx words before, anchor cycle): the loop it is in, by states
        self.misses = 0  # stretches run past the instant asked for that gave no table entry
        self.short: set = set()  # shapes of short stretches stepped once: run past the instant when seen again
        self.per_us = (sm.config.SYS_HZ * 256, sm.config.div256 * 1_000_000)  # cycles a µs, as a fraction

    def __deepcopy__(self, memo):
        twin = Running.__new__(Running)
        memo[id(self)] = twin
        twin.__dict__.update(self.__dict__)  # (numbers, and the table's entries, which never change: shared)
        twin.sm = copy.deepcopy(self.sm, memo)
        return twin

    def cycle_at(self, t_us: int) -> int:
        """The first cycle at or after ``t_us`` (exact: cycles per µs = SYS_HZ*256 / (div256 * 10**6))."""
        mul, den = self.per_us
        return -((self.t0_us - t_us) * mul // den)

    def time_us(self, cycle: int) -> float:
        mul, den = self.per_us
        return self.t0_us + cycle * den / mul


RELEASED = -1
"""What a pin carries while a state machine has made it an input (``pindirs`` 0): nothing
driven (the plant's parts take -1 as a line let go, ``sim_plant.catalogue.qtr``)."""


class PioBlock:
    """PIO0 or PIO1: up to four state machines sharing memory, IRQ flags and GPIOs."""

    def __init__(self, block_id: int = 0):
        self.block_id = block_id
        self.memory = [0] * 32
        self.irq_flags = 0
        self.gpio_in = 0
        self.levels: dict[int, int] = {}  # gpio -> the level a state machine drives
        self.dirs: dict[int, int] = {}  # gpio -> 1 output, 0 input (pindirs)
        self.events: list[tuple] = []  # (t_us float, gpio, level or RELEASED): driven changes, in time order
        self.record_events = True  # False: nobody reads ``events`` (only the levels driven last)
        self.irqs: list[tuple] = []  # (t_us float, flag, sm_id): flags 0..3 raised (the CPU's IRQ)
        self.irq_clears = 0  # flags 0..3 the CPU's interrupt handler clears as they are raised
        self.running: dict[int, Running] = {}
        self.steps = 0  # instructions stepped (the cost)
        self.replays = 0  # stretches taken from a table instead
        self.version = 0  # bumped by a change from outside for every state machine (the firmware's IRQ flags);
        # a pin, a FIFO access, an exec forget the loops of those it concerns (set_input, touch_sm)
        self._run: Running | None = None  # (the state machine stepping: the instant of a drive)
        self._now_us = 0.0
        self._log: list | None = None  # (cycle, call, args): what the stretch watched for a period did
        self._cycle = 0
        self.pure = True  # its program touches nothing but its own state machine (no IRQ, no exec): pure()
        self.relative = False  # ... and reads the pins only from in_base (machine.relative): tables shared

    def __deepcopy__(self, memo):
        """Numbers, containers of numbers and tuples, and the state machines."""
        twin = PioBlock.__new__(PioBlock)
        memo[id(self)] = twin
        twin.__dict__.update(self.__dict__)
        twin.memory, twin.levels, twin.dirs = list(self.memory), dict(self.levels), dict(self.dirs)
        twin.events, twin.irqs = list(self.events), list(self.irqs)
        twin.running = {sm_id: copy.deepcopy(run, memo) for sm_id, run in self.running.items()}
        twin._run = None if self._run is None else copy.deepcopy(self._run, memo)
        twin._log = None if self._log is None else copy.deepcopy(self._log, memo)
        return twin

    def fork(self) -> "PioBlock":
        """A copy to run ahead on (``host/rig/hardware/pio_ahead.py``, ``pio_out.py``), as
        :func:`copy.deepcopy` makes it but without its machinery: taken between two runs (no
        state machine stepping, its registers numbers), the memory and the tables shared
        (never changed in place: :meth:`load` replaces them)."""
        if self._run is not None or self._log is not None:
            return copy.deepcopy(self)
        twin = PioBlock.__new__(PioBlock)
        twin.__dict__.update(self.__dict__)
        twin.levels, twin.dirs = dict(self.levels), dict(self.dirs)
        twin.events, twin.irqs = list(self.events), list(self.irqs)
        running = twin.running = {}
        for sm_id, run in self.running.items():
            sm = run.sm
            if not trace.plain(sm):
                return copy.deepcopy(self)
            copied = Running.__new__(Running)
            copied.__dict__.update(run.__dict__)
            copied.sm = twin_sm = StateMachine.__new__(StateMachine)
            twin_sm.__dict__.update(sm.__dict__)
            twin_sm.block = twin
            twin_sm.tx, twin_sm.rx = deque(sm.tx), deque(sm.rx)
            running[sm_id] = copied
        return twin

    # -- configuration ---------------------------------------------------------------
    def load(self, memory: list[int]) -> None:
        self.memory = list(memory) + [0] * (32 - len(memory))
        self.pure = pure(self.memory)
        self.relative = self.pure and relative(self.memory)
        for run in self.running.values():
            run.entries, run.table, run.unaliased, run.misses, run.short = {}, None, set(), 0, set()
            run.sm.read_mask = read_mask(self.memory, run.sm)
            run.sm.key_rot = run.sm.in_base if self.relative else None

    def init(self, sm_id: int, config: PioConfig, t_us: int) -> StateMachine:
        old = self.running.get(sm_id)
        sm = StateMachine(self, sm_id, config)
        sm.read_mask = read_mask(self.memory, sm)
        if old is not None:
            sm.tx, sm.rx = old.sm.tx, old.sm.rx
        run = self.running[sm_id] = Running(sm, t_us)
        if self.relative:  # (a sibling with the same registers but in_base: one table for both)
            sm.key_rot = sm.in_base
            for other_id, other in self.running.items():
                if other_id != sm_id and other.sm.key_rot is not None and _alike(other.sm.config, config):
                    run.entries, run.unaliased, run.short = other.entries, other.unaliased, other.short
                    break
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

    def touch_sm(self, sm_id: int) -> None:
        """Something outside changed what state machine ``sm_id`` alone may do next (its
        FIFOs, an exec, its start): the loop it was in is no longer known; the others' are."""
        run = self.running.get(sm_id)
        if run is not None:
            run.orbit_version = -1

    def drive(self, gpio: int, level: int, dirs: bool = False) -> None:
        """A state machine drives ``gpio``'s level, or with ``dirs`` its direction (1 an
        output, 0 an input). ``events`` has what the pin carries as the plant sees it: the
        level of an output, :data:`RELEASED` from the cycle it becomes an input (the line let
        go), its OUT level again from the cycle it becomes an output; a level driven while
        it is an input is kept, not seen. (A pin no program or ``*_init`` gave a direction is
        taken as an output.)"""
        if self._log is not None:
            self._log.append((self._cycle, self.drive, (gpio, level, dirs)))
        if dirs:
            if self.dirs.get(gpio, 1) != level:
                self.events.append((self.now_us(), gpio, self.levels.get(gpio, 0) if level else RELEASED))
            self.dirs[gpio] = level
            return
        if self.levels.get(gpio) != level:
            self.levels[gpio] = level
            if self.dirs.get(gpio, 1):
                self.events.append((self.now_us(), gpio, level))

    def raise_irq(self, flag: int, sm_id: int) -> None:
        if self._log is not None:
            self._log.append((self._cycle, self.raise_irq, (flag, sm_id)))
        if flag < 4:
            self.irqs.append((self.now_us(), flag, sm_id))
            if self.irq_clears >> flag & 1:  # (the interrupt is enabled: its handler clears it at once)
                return
        self.irq_flags |= 1 << flag

    def set_input(self, gpio: int, level: int) -> None:
        """A pin's level from the plant: the loop of each state machine that reads it (or has
        an instruction pending from an exec, which may read any) is no longer known; the
        others go on along theirs (a pin a program does not read changes nothing it does)."""
        for run in self.running.values():
            sm = run.sm
            if sm.read_mask >> gpio & 1 or sm.pending_exec is not None:
                run.orbit_version = -1
        if level:
            self.gpio_in |= 1 << gpio
        else:
            self.gpio_in &= ~(1 << gpio)

    # -- time --------------------------------------------------------------------------
    def advance(self, t_us: int, changes=()) -> None:
        """Run every active state machine to ``t_us`` (not its cycle at ``t_us``), the pin
        changes ``(t_us, gpio, level)`` (in time order, none after ``t_us``) applied as
        they come."""
        i, n = 0, len(changes)
        while i < n:
            i = walk.walk(self, t_us, changes, i)  # (along the table while it holds: walk.py)
            if i > n:
                return
            if i == n:
                break
            t_change, gpio, level = changes[i]
            if self.record_events or not self.pure or self._reads(gpio):
                self._run_all(t_change)
            self.set_input(gpio, level)
            i += 1
        self._run_all(t_us)

    def _reads(self, gpio: int) -> bool:
        """Whether an active state machine may read ``gpio`` (its program's pins, or any with
        an exec pending). One that does not goes on from before the change to after it in one
        run, to the same state: in a pure block (:func:`pure`: no IRQ flag, no exec) nothing
        but its FIFOs and the pins it reads moves a state machine, and with ``events`` not
        kept no order of the state machines' drives is seen (a servo's or a LED strip's
        program beside the ranger's echo)."""
        for run in self.running.values():
            if run.active and (run.sm.read_mask >> gpio & 1 or run.sm.pending_exec is not None):
                return True
        return False

    def _run_all(self, t_us: int) -> None:
        for run in self.running.values():
            if run.active:
                mul, den = run.per_us  # (run.cycle_at(t_us), inline)
                c_end = -((run.t0_us - t_us) * mul // den)
                if run.cycle < c_end:
                    run_cycles(self, run, c_end)

    @property
    def idle(self) -> bool:
        """No state machine runs: time and pin changes do nothing to the block."""
        return not any(run.active for run in self.running.values())

    def probe(self, sm_id: int, t_us: int, horizon_us: int, want, in_place: bool = False) -> float | None:
        """When ``want(sm)`` first holds if the pins stay as they are, looking no further
        than ``horizon_us`` (None: not by then); the block itself is not moved (``in_place``:
        it is, to that instant, or to the horizon: a copy that is thrown away after)."""
        twin = self if in_place else self.fork()
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
    nothing changed, is skipped at once; a stretch after a change seen before with the same
    state but X and Y is taken from the table: :mod:`.trace`)."""
    sm = run.sm
    c = run.cycle
    if c >= c_end:
        return
    if run.orbit and run.orbit_version == block.version:
        if run.table is not None:
            run.cycle = run.table[0].at(run, c_end)
            return
        c += (c_end - c) // run.orbit * run.orbit
    elif not (sm.set_count or sm.out_count or sm.side_count) and trace.plain(sm):
        c = _stretch(block, run, c, c_end)
        if c < c_end and run.table is not None and run.orbit_version == block.version:
            run.cycle = run.table[0].at(run, c_end)
            return
    run.cycle = _steps(block, run, c, c_end, False)[0]


def _steps(block: PioBlock, run: Running, c: int, c_end: int, stop_at_repeat: bool, path: list | None = None) -> tuple:
    """The stepping loop: (the cycle it got to, the period of the loop it found when
    ``stop_at_repeat``, else 0; whether it drove a pin or raised an IRQ on the way); each
    step's state kept in ``path`` (by the cycles since ``c``, :func:`trace.capture`)."""
    sm = run.sm
    c0 = c
    rx_from = len(sm.rx)
    seen: dict = {}
    heads: dict = {}  # pc -> (key, log length): the last pass of a loop through it
    counting = COUNTDOWN and trace.plain(sm)
    block._log = log = []
    block._run = run
    step = sm.step
    try:
        while c < c_end:
            pc = sm.pc
            block._cycle = c
            c += step()
            block.steps += 1
            if path is not None:
                path.append((c - c0, trace.raw(sm, rx_from)))
            if sm.pc > pc:
                continue
            key = sm.key()
            first = seen.get(key)
            if first is None:
                if len(seen) >= SEEN_MAX:
                    seen.clear()
                    log.clear()
                    heads.clear()
                seen[key] = (c, len(log))
                if counting:
                    head = heads.get(sm.pc)
                    mark = _quiet_mark(block)
                    heads[sm.pc] = (key, mark)
                    if head is not None and head[1] == mark and c < c_end:
                        name = _counter(head[0], key)
                        if name is not None:
                            c = _count_down(block, run, name, c, c_end, log)
                            heads.clear()
                continue
            period = c - first[0]
            if stop_at_repeat:
                return c, period, bool(log)
            if len(log) == first[1]:  # (a loop that drives nothing: remembered until something changes)
                run.orbit, run.orbit_version, run.table = period, block.version, None
            else:
                run.drive_period = period
            c = _skip_periods(block, run, first, c, c_end, log)
            seen.clear()
            log.clear()
    finally:
        block._log = None
        block._run = None
    return c, 0, False


def _counter(old: tuple, new: tuple) -> str | None:
    """ "x" or "y" when two passes through a loop head differ in that register only, one
    less each pass (a ``jmp x--`` count, a PWM's ``jmp y--``), else None."""
    if old[0] != new[0] or old[3:] != new[3:]:
        return None
    if old[1] == new[1] and (old[2] - new[2]) & trace.MASK == 1:
        return "y"
    if old[2] == new[2] and (old[1] - new[1]) & trace.MASK == 1:
        return "x"
    return None


def _quiet_mark(block: PioBlock) -> tuple:
    """What a pass that changes nothing outside the state machine keeps as it is: the pins'
    changes and the IRQs raised so far, the pin directions (a side-set of the level a pin
    already has, on each pass, changes none of them)."""
    return len(block.events), len(block.irqs), tuple(block.dirs.items())


def _count_down(block: PioBlock, run: Running, name: str, c: int, c_end: int, log: list) -> int:
    """``run``'s state machine at cycle ``c`` at a loop head, its counter ``name`` one less
    each pass and nothing else changing: run one pass with the counter as a symbol
    (:class:`trace.Sym`: each comparison of it kept as a guard), then jump over the passes
    that would do the same (no drive, no IRQ, every guard as in this pass: the counter
    meets none of the values it is compared with) as long as they end before ``c_end``.
    The cycle it got to (the pass run, plus the passes jumped over); the state exactly what
    single steps would leave at that cycle. (A pass's drives that change nothing, a side-set
    of the level the pin has, are in the log once: replaying a period without the others
    leaves the same levels.)"""
    sm = run.sm
    v = getattr(sm, name)
    head_pc, mark = sm.pc, _quiet_mark(block)
    start = sm.key()
    rec = trace.Recorder()
    setattr(sm, name, trace.Sym(v, name, False, 0, rec))
    c1, closed = c, False
    try:
        for _ in range(PASS_MAX):
            pc = sm.pc
            block._cycle = c1
            c1 += sm.step()
            block.steps += 1
            if sm.pc <= pc and sm.pc == head_pc:
                closed = True
                break
            if c1 >= c_end or rec.tainted or _quiet_mark(block) != mark:
                break
        counter = getattr(sm, name)
        others = (sm.isr, sm.osr, sm.y if name == "x" else sm.x)
        fit = (
            closed
            and c1 < c_end
            and _quiet_mark(block) == mark
            and not rec.tainted
            and isinstance(counter, trace.Sym)
            and counter.form() == (name, False, trace.MASK)
            and all(type(r) is int for r in others)
            and all(type(w) is int for w in sm.rx)
        )
    finally:
        _concrete(sm)
    if not fit:
        return c1
    end = sm.key()
    i = 1 if name == "x" else 2
    if end[:i] + end[i + 1 :] != start[:i] + start[i + 1 :]:
        return c1
    passes = 1 << 32  # the first pass (0: the one run) whose guards come out otherwise
    for kind, form, other, result in rec.guards:
        base, neg, off = form
        if kind != "==" or base != name or result or type(other) is not int:
            return c1
        # the counter at pass j is v - j: (±(v - j) + off) == other first holds at j
        j = ((other + v - off) if neg else (v + off - other)) & trace.MASK
        passes = min(passes, j or 1 << 32)
    period = c1 - c
    m = min(passes - 1, (c_end - c1) // period)
    if m <= 0:
        return c1
    setattr(sm, name, (getattr(sm, name) - m) & trace.MASK)
    return c1 + m * period


def _stretch(block: PioBlock, run: Running, c0: int, c_end: int) -> int:
    """From a change to the loop it leads to: from the table when the same shape with this
    X and Y was seen, else run with X and Y as symbols (and kept when it is fit). A table
    entry keeps the stretch's states before its loop too, so an instant before the loop is
    one restore as well (a decoder's FIFO refilled after a read); a state machine whose
    program touches nothing outside itself (:func:`pure`) is run with symbols past
    ``c_end``, to its loop, and put back at ``c_end``'s state from the states it went
    through, so that a short stretch (a read's 1 µs probe) is learnt too."""
    sm = run.sm
    key = trace.shape(sm)
    if key in run.unaliased:  # (a shift register equal to X or Y by chance, and used as a number)
        key = trace.shape(sm, aliases=False)
    x, y, rx_old = sm.x, sm.y, list(sm.rx)
    for entry in run.entries.get(key, ()):
        if (c0 + entry.cycles <= c_end or entry.path) and entry.holds(x, y):
            run.table = (entry, x, y, rx_old, c0 + entry.cycles)
            run.orbit, run.orbit_version = entry.period, block.version
            block.replays += 1
            return entry.at(run, c_end)  # (straight to c_end's state along the loop: one restore)
    limit = _limit(block, run, key, c0, c_end)
    if limit is None:
        return c0  # (too short to find a loop and go round it once more: single steps cost less)
    rec = trace.Recorder()
    sm.x, sm.y = trace.Sym(x, "x", False, 0, rec), trace.Sym(y, "y", False, 0, rec)
    if key[1] in ("x", "y"):
        sm.isr = sm.x if key[1] == "x" else sm.y
    if key[3] in ("x", "y"):
        sm.osr = sm.x if key[3] == "x" else sm.y
    path = [(0, trace.raw(sm, len(rx_old)))]
    entry = None
    try:
        c, period, drove = _steps(block, run, c0, limit, True, path)
        if rec.tainted and (key[1] in ("x", "y") or key[3] in ("x", "y")):
            run.unaliased.add(key)
        if period and not drove and not rec.tainted and c + period <= limit:
            table = _one_period(block, run, c, period, len(rx_old), path, c0)
            if table is not None and not rec.tainted:
                entry = trace.Entry(list(rec.guards), c - c0, period, table, [p for p in path if p[0] < c - c0])
                entries = run.entries
                if len(entries) >= trace.ENTRIES_MAX:
                    entries.clear()
                entries.setdefault(key, []).append(entry)
                run.table = (entry, x, y, rx_old, c + period)
                run.orbit, run.orbit_version = period, block.version
            c += period
    finally:
        _concrete(sm)
    if c <= c_end or limit == c_end:
        return c
    return _put_back(run, entry, path, x, y, rx_old, c0, c_end, c)


def _limit(block: PioBlock, run: Running, key: tuple, c0: int, c_end: int) -> int | None:
    """How far a stretch that missed the table is run with symbols: past ``c_end`` to
    ``AHEAD_CYCLES`` for a pure program (:func:`pure`) that has not missed too often, else
    to ``c_end``; None: not at all (a short stretch, stepped; the first time its shape comes,
    when it could be run ahead: the next time it is)."""
    sm = run.sm
    ahead = block.pure and run.misses < AHEAD_MISSES and sm.pending_exec is None and not sm.irq_waiting
    if c_end - c0 < SHORT_CYCLES and (not ahead or key not in run.short):
        if ahead:
            if len(run.short) >= SEEN_MAX:
                run.short.clear()
            run.short.add(key)
        return None
    return max(c_end, c0 + AHEAD_CYCLES) if ahead else c_end


def _put_back(run: Running, entry, path: list, x: int, y: int, rx_old: list, c0: int, c_end: int, c: int) -> int:
    """A stretch run past ``c_end`` (to cycle ``c``) put back at its first step boundary at or
    after ``c_end``: along ``entry`` when it was kept, else from the states it went through."""
    if entry is not None:
        run.table = (entry, x, y, rx_old, c0 + entry.cycles)
        return entry.at(run, c_end)
    run.misses += 1
    for offset, state in path:
        if c0 + offset >= c_end:
            trace.restore(run.sm, state, x, y, rx_old)
            return c0 + offset
    return c  # (not reached: the path ends where the state machine is, past c_end)


def _alike(a: PioConfig, b: PioConfig) -> bool:
    """Two state machines' registers the same but for ``in_base`` (PINCTRL bits 15..19)."""
    in_base = 0x1F << 15
    return (
        a.execctrl == b.execctrl
        and a.shiftctrl == b.shiftctrl
        and a.pinctrl & ~in_base == b.pinctrl & ~in_base
        and a.div256 == b.div256
        and a.pc == b.pc
    )


def pure(memory: list) -> bool:
    """A program that changes nothing outside its state machine and reads no IRQ flag: no
    ``irq``, no ``wait irq``, no ``mov exec`` or ``out exec`` (which could run either). Its
    state machine can be run ahead of an instant and put back (:func:`_stretch`)."""
    for word in memory:
        op = word >> 13
        irq = op == 6 or (op == 1 and word >> 5 & 3 == 2)
        if irq or (op == 5 and word >> 5 & 7 == 4) or (op == 3 and word >> 5 & 7 == 7):
            return False
    return True


def _one_period(block: PioBlock, run: Running, c: int, period: int, rx_from: int, path: list, c0: int) -> list | None:
    """Step one period from ``c`` (the loop's state), keeping the state at each step (in
    ``path`` too, by the cycles since ``c0``)."""
    sm = run.sm
    table = [(0, trace.capture(sm, rx_from))]
    block._run = run
    try:
        c_start = c
        while True:
            block._cycle = c
            c += sm.step()
            block.steps += 1
            state = trace.capture(sm, rx_from)
            path.append((c - c0, state))
            if c - c_start >= period:
                break
            table.append((c - c_start, state))
    finally:
        block._run = None
    return table if c - c_start == period and path[-1][1] == table[0][1] else None


def _concrete(sm) -> None:
    """X, Y, ISR, OSR and the RX words as numbers again (their symbols' values)."""
    for name in ("x", "y", "isr", "osr"):
        v = getattr(sm, name)
        if isinstance(v, trace.Sym):
            setattr(sm, name, v.c)
    if any(isinstance(v, trace.Sym) for v in sm.rx):
        sm.rx = type(sm.rx)(v.c if isinstance(v, trace.Sym) else v for v in sm.rx)


def _skip_periods(block, run, first, c, c_end, log) -> int:
    """``sm`` is at cycle ``c`` in the state it had at ``first[0]``: jump over the whole
    periods that fit before ``c_end``, replaying the period's drives for each."""
    c_first, i_first = first
    period = c - c_first
    periods = (c_end - c) // period
    if periods <= 0:
        return c
    pattern = log[i_first:]
    passes = range(1, periods + 1) if pattern else ()
    if not block.record_events and all(call == block.drive for _cycle, call, _args in pattern):
        passes = passes[-1:]  # (drives alone, no IRQ, and no one reads the changes: the last period's levels)
    block._log = None
    try:
        for k in passes:
            for cycle, call, args in pattern:
                block._cycle = cycle + k * period
                call(*args)
    finally:
        block._log = log
    return c + periods * period
