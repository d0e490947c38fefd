"""The stretch after a pin change, replayed from a table (``docs/shim.md``, "PIO", cost).

A state machine's X and Y are often counts the program only moves, compares with 0 (or
with each other) and copies (a quadrature decoder's count): the stretch from a pin change
until its loop repeats does the same whatever their values, but for those comparisons.
It is run once with X and Y as symbols (:class:`Sym`: ``±X + k`` or ``±Y + k``, which
records each comparison's outcome as a guard, and marks the stretch unfit for the table
when used any other way: shifted, masked, driven, jumped to); then the same start (every
other field, the pins) with an X and Y that pass the guards ends where the table says.
The loop it ends in is kept as its states along one period (:class:`Entry`), so a stretch
with nothing changed goes to any cycle at once too: an edge costs two look-ups, not the
few dozen instructions of its stretch.
"""

from bisect import bisect_left
from collections import deque
from itertools import islice

MASK = 0xFFFFFFFF
ENTRIES_MAX = 4096  # table entries a state machine keeps (then it starts afresh)


class Recorder:
    def __init__(self):
        self.guards: list[tuple] = []
        self.tainted = False


class Sym:
    """A register's value as ``(-B if neg else B) + off`` of the stretch's starting X or Y
    (``base``), with its concrete value ``c`` (what the step computes with)."""

    __slots__ = ("c", "base", "neg", "off", "rec")

    def __init__(self, c, base, neg, off, rec):
        self.c, self.base, self.neg, self.off, self.rec = c & MASK, base, neg, off & MASK, rec

    def form(self) -> tuple:
        return (self.base, self.neg, self.off)

    def _new(self, c, neg, off):
        return Sym(c, self.base, neg, off, self.rec)

    def __invert__(self):
        return self._new(~self.c, not self.neg, -self.off - 1)

    def __sub__(self, k):
        if type(k) is int:
            return self._new(self.c - k, self.neg, self.off - k)
        return self._taint() - k

    def __add__(self, k):
        if type(k) is int:
            return self._new(self.c + k, self.neg, self.off + k)
        return self._taint() + k

    def __and__(self, mask):
        return self if mask == MASK else self._taint() & mask

    __rand__ = __and__

    def __eq__(self, other):
        if isinstance(other, Sym):  # (a state compared with a state: the same for every X, Y)
            return self.form() == other.form()
        result = self.c == other
        self.rec.guards.append(("==", self.form(), other, result))
        return result

    def __ne__(self, other):
        if isinstance(other, Sym):  # (jmp x!=y)
            result = self.c != other.c
            self.rec.guards.append(("S!=", self.form(), other.form(), result))
            return result
        result = self.c != other
        self.rec.guards.append(("==", self.form(), other, not result))
        return result

    def __hash__(self):
        return hash(self.form())

    def _taint(self) -> int:
        self.rec.tainted = True
        return self.c

    def __rshift__(self, k):
        return self._taint() >> k

    def __lshift__(self, k):
        return self._taint() << k

    def __or__(self, k):
        return self._taint() | k

    __ror__ = __or__

    def __rlshift__(self, k):
        return k << self._taint()

    def __rrshift__(self, k):
        return k >> self._taint()

    def __xor__(self, k):
        return self._taint() ^ k

    def __format__(self, spec):
        return format(self._taint(), spec)

    def __index__(self):
        return self._taint()

    __int__ = __index__

    def __bool__(self):
        return bool(self._taint())

    def __lt__(self, k):
        return self._taint() < k

    def __gt__(self, k):
        return self._taint() > k


def spec(v):
    return v.form() if isinstance(v, Sym) else v


def value(s, x: int, y: int) -> int:
    """A register as a state keeps it (a number, a form, or a :class:`Sym` in a stretch's
    states before its loop: :func:`raw`) for this X and Y."""
    if type(s) is tuple:
        base, neg, off = s
        b = x if base == "x" else y
        return ((-b if neg else b) + off) & MASK
    if type(s) is Sym:
        b = x if s.base == "x" else y
        return ((-b if s.neg else b) + s.off) & MASK
    return s


def alias(v: int, x: int, y: int):
    """A shift register's value as the shape keeps it: "x" or "y" when it holds a copy
    (not 0: an unused register and an empty shift register are 0 by chance, mostly)."""
    if not v:
        return v
    return "x" if v == x else ("y" if v == y else v)


def shape(sm, aliases: bool = True) -> tuple:
    """What a stretch's table entry is kept under: the state but X, Y (and, ``aliases``, a
    shift register holding a copy of one) and the RX words; of the pins, those its program
    reads (``machine.read_mask``: the other decoder's edges make no new shape)."""
    x, y = (sm.x, sm.y) if aliases else (None, None)
    return (
        sm.pc,
        alias(sm.isr, x, y),
        sm.isr_n,
        alias(sm.osr, x, y),
        sm.osr_n,
        len(sm.rx),
        tuple(sm.tx),
        sm.pending_exec,
        sm.irq_waiting,
        sm.block.irq_flags,
        pins_of(sm.block.gpio_in, sm.read_mask, sm.key_rot, sm.pending_exec),
    )


def pins_of(gpio_in: int, mask: int, rot, pending) -> int | tuple:
    """The pins as a shape keeps them: those the program reads (``mask``; all of them
    with an instruction pending from an exec, which may read any), turned by ``rot`` (the
    state machine's ``in_base``) when its tables are shared (``machine.relative``): the same
    pins counted from ``in_base`` give the same key; with an exec pending, its ``in_base``
    kept beside them (an exec'd ``wait gpio`` reads a pin by its number)."""
    if pending is not None:
        return gpio_in if rot is None else (gpio_in, rot)
    pins = gpio_in & mask
    if rot:
        pins = ((pins >> rot) | (pins << (32 - rot))) & MASK
    return pins


def shape_of_state(state: tuple, isr, osr, n_rx: int, gpio_in: int, mask: int, rot=None) -> tuple:
    """:func:`shape` of a state machine at ``state`` (as :func:`capture` keeps it), given its
    shift registers as :func:`alias` keeps them, its RX words' count and the pins (walk.py:
    the next stretch's key along a loop, the registers not restored); ``mask`` the pins its
    program reads, ``rot`` its shapes' turn (:func:`pins_of`)."""
    pc, _x, _y, _isr, isr_n, _osr, osr_n, pending, waiting, flags, tx, _rx_new = state
    return (pc, isr, isr_n, osr, osr_n, n_rx, tx, pending, waiting, flags, pins_of(gpio_in, mask, rot, pending))


def capture(sm, rx_from: int) -> tuple:
    """A state machine's state, X and Y as their forms (each step of a stretch run with symbols)."""
    x, y, isr, osr, rx = sm.x, sm.y, sm.isr, sm.osr, sm.rx
    return (
        sm.pc,
        x if type(x) is int else x.form(),
        y if type(y) is int else y.form(),
        isr if type(isr) is int else spec(isr),
        sm.isr_n,
        osr if type(osr) is int else spec(osr),
        sm.osr_n,
        sm.pending_exec,
        sm.irq_waiting,
        sm.block.irq_flags,
        tuple(sm.tx) if sm.tx else (),
        tuple(spec(v) for v in islice(rx, rx_from, None)) if len(rx) > rx_from else (),
    )


def raw(sm, rx_from: int) -> tuple:
    """:func:`capture` with the registers as they are (symbols kept as :class:`Sym`, which
    :func:`value` and :func:`restore` read as their forms): a stretch's states before its
    loop, one a step, are only restored, and mostly never."""
    rx = sm.rx
    return (
        sm.pc,
        sm.x,
        sm.y,
        sm.isr,
        sm.isr_n,
        sm.osr,
        sm.osr_n,
        sm.pending_exec,
        sm.irq_waiting,
        sm.block.irq_flags,
        tuple(sm.tx) if sm.tx else (),
        tuple(islice(rx, rx_from, None)) if len(rx) > rx_from else (),
    )


def restore(sm, state: tuple, x: int, y: int, rx_old: list) -> None:
    pc, sx, sy, isr, isr_n, osr, osr_n, pending, waiting, flags, tx, rx_new = state
    sm.pc, sm.isr_n, sm.osr_n, sm.pending_exec, sm.irq_waiting = pc, isr_n, osr_n, pending, waiting
    sm.x = sx if type(sx) is int else value(sx, x, y)
    sm.y = sy if type(sy) is int else value(sy, x, y)
    sm.isr = isr if type(isr) is int else value(isr, x, y)
    sm.osr = osr if type(osr) is int else value(osr, x, y)
    sm.block.irq_flags = flags
    if tx or sm.tx:
        sm.tx = deque(tx)
    if rx_new or len(sm.rx) != len(rx_old):  # (else the RX FIFO holds what it held)
        sm.rx = deque(rx_old + [value(v, x, y) for v in rx_new])


class Entry:
    """A stretch: its guards, its length to the loop, the loop's period and its states
    along one period ((offset, state), offset 0 the state the stretch ends in)."""

    def __init__(self, guards, cycles, period, table, path=()):
        self.guards = guards
        self.path = path  # [(cycles since the change, state)]: the stretch's states before its loop
        self.cycles = cycles
        self.period = period
        self.offsets = [off for off, _state in table]
        self.states = [state for _off, state in table]
        self.shapes: dict = {}  # (state index, pins, RX words) -> a stretch's shape from it (walk.py)
        self.checks = None  # the guards as (on X, neg, off, other, result), when each compares a form with a number
        if all(kind == "==" and type(b) is int and a[0] in ("x", "y") for kind, a, b, _r in guards):
            self.checks = tuple((a[0] == "x", a[1], a[2], b, result) for _kind, a, b, result in guards)
        flags = {state[9] for state in self.states}  # the block's IRQ flags along the loop
        self.irq_flags = flags.pop() if len(flags) == 1 else -1  # (-1: they change on the way)

    def holds(self, x: int, y: int) -> bool:
        checks = self.checks
        if checks is not None:  # (every guard a form of X or Y compared with a number: the common case)
            for on_x, neg, off, other, result in checks:
                b = x if on_x else y
                if ((((-b if neg else b) + off) & MASK) == other) != result:
                    return False
            return True
        for kind, a, b, result in self.guards:
            if kind == "==":
                if (value(a, x, y) == b) != result:
                    return False
            elif (value(a, x, y) != value(b, x, y)) != result:
                return False
        return True

    def at(self, run, c_end: int) -> int:
        """Put ``run``'s state machine at its first step boundary at or after ``c_end``
        along this loop (anchored where ``run.table`` says): the cycle it is at."""
        _entry, x, y, rx_old, anchor = run.table
        if c_end < anchor and self.path:  # (before the loop: along the stretch's own states)
            c0 = anchor - self.cycles
            path = self.path
            i = bisect_left(path, (c_end - c0,))
            offset, state = path[i] if i < len(path) else (self.cycles, self.states[0])
            restore(run.sm, state, x, y, rx_old)
            return c0 + offset
        k, r = divmod(c_end - anchor, self.period)
        j = bisect_left(self.offsets, r)
        if j == len(self.offsets):
            k, j = k + 1, 0
        restore(run.sm, self.states[j], x, y, rx_old)
        return anchor + k * self.period + self.offsets[j]


def plain(sm) -> bool:
    return type(sm.x) is int and type(sm.y) is int and type(sm.isr) is int and type(sm.osr) is int
