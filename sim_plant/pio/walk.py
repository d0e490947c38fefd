"""A batch of pin changes walked along the stretch table, the state machines left abstract
between them (``docs/shim.md``, "PIO", cost).

:meth:`PioBlock.advance` over a list of changes does, for each: run every state machine to
the change's instant, set the pin, and at the next instant look the stretch up
(:func:`block._stretch`) and go along its loop (:meth:`trace.Entry.at`), restoring the
registers each time. When every stretch is in the table, nothing needs the registers
between two changes but the next look-up: this walk keeps each state machine as (its
table entry, X, Y, the RX words, the anchor, the cycle, the loop state it is at) and builds
the next look-up's key from the entry's state directly, restoring the registers once, at
the end of the batch. It takes exactly the slow path's steps (the same keys, guards, cycles
and replay count: ``host/tests/test_pio_walk.py`` runs both on the same changes and
compares them); the first change whose stretch is not in the table, or whose state machine
drives pins or raises IRQ flags, ends the walk, and the slow path goes on from it.
"""

from bisect import bisect_left

from sim_plant.pio import trace

_value = trace.value
_MASK = MASK = trace.MASK
_alias = trace.alias


class _Walker:
    """One active state machine: concrete (``entry`` None: its registers are its state, a
    stretch pending) or along ``entry``'s loop at state ``j``."""

    __slots__ = ("run", "entry", "x", "y", "rx", "anchor", "cycle", "j", "pending", "t0", "mul", "den", "reads")

    def __init__(self, run, pending: bool):
        self.run = run
        self.entry = None
        self.cycle = run.cycle
        self.pending = pending
        self.t0 = run.t0_us
        self.mul = run.sm.config.SYS_HZ * 256
        self.den = run.sm.config.div256 * 1_000_000
        self.reads = MASK if run.sm.pending_exec is not None else run.sm.read_mask  # (the pins it reads)
        if not pending:
            self.entry, self.x, self.y, self.rx, self.anchor = run.table
            # (None: still on the stretch before its loop, where the state machine is as it is)
            self.j = _position(self.entry, self.cycle - self.anchor) if self.cycle >= self.anchor else None

    def key(self, block) -> tuple:
        """(the stretch's shape as :func:`trace.shape` gives it, X, Y, the RX words)."""
        if self.entry is None or self.j is None:  # (its registers are its state)
            sm = self.run.sm
            return trace.shape(sm), sm.x, sm.y, list(sm.rx)
        x, y = self.x, self.y
        sm = self.run.sm
        pins, rot = block.gpio_in & sm.read_mask, sm.key_rot  # (trace.pins_of, inline)
        if rot:
            pins = ((pins >> rot) | (pins << (32 - rot))) & _MASK
        mkey = (self.j, pins, len(self.rx))
        known = self.entry.shapes.get(mkey)
        if known is None:
            known = self.entry.shapes[mkey] = _shape_of(self.entry.states[self.j], mkey)
        shape, danger_x, danger_y, x_eq_y, sx, sy, rx_new = known
        xv = sx if type(sx) is int else _value(sx, x, y)
        yv = sy if type(sy) is int else _value(sy, x, y)
        rx = self.rx + [_value(v, x, y) for v in rx_new] if rx_new else self.rx
        if shape is None or xv in danger_x or yv in danger_y or (x_eq_y and xv == yv):
            shape = self._shape(self.entry.states[self.j], xv, yv, len(rx), block)
        return shape, xv, yv, rx

    def _shape(self, state, xv: int, yv: int, n_rx: int, block) -> tuple:
        isr, osr = _value(state[3], self.x, self.y), _value(state[5], self.x, self.y)
        sm = self.run.sm
        return trace.shape_of_state(
            state, _alias(isr, xv, yv), _alias(osr, xv, yv), n_rx, block.gpio_in, sm.read_mask, sm.key_rot
        )

    def resolve(self, block, c_end: int) -> bool:
        """The pending stretch from the table (False: not there, or not one to walk)."""
        run = self.run
        shape, x, y, rx = self.key(block)
        if run.unaliased and shape in run.unaliased:
            return False
        c0 = self.cycle
        for entry in run.entries.get(shape, ()):
            if (c0 + entry.cycles <= c_end or entry.path) and entry.holds(x, y):
                break  # (the slow path's choice: block._stretch)
        else:
            return False
        if c0 + entry.cycles > c_end:  # (an instant before its loop: the slow path restores it)
            return False
        if entry.irq_flags != block.irq_flags:  # (a restore sets them: only a loop that keeps them)
            return False
        self.entry, self.x, self.y, self.rx, self.anchor = entry, x, y, rx, c0 + entry.cycles
        self.pending = False
        block.replays += 1
        return True

    def go(self, c_end: int) -> None:
        """Along the loop to its first step boundary at or after ``c_end`` (:meth:`trace.Entry.at`)."""
        entry = self.entry
        k, r = divmod(c_end - self.anchor, entry.period)
        offsets = entry.offsets
        j = bisect_left(offsets, r)
        if j == len(offsets):
            k, j = k + 1, 0
        self.j = j
        self.cycle = self.anchor + k * entry.period + offsets[j]

    def settle(self, block) -> None:
        """The registers as the slow path would have left them."""
        run = self.run
        run.cycle = self.cycle
        entry = self.entry
        if entry is None or self.j is None:
            return
        run.table = (entry, self.x, self.y, self.rx, self.anchor)
        run.orbit = entry.period
        run.orbit_version = -1 if self.pending else block.version
        sm = run.sm
        state = entry.states[self.j]
        trace.restore(sm, state, self.x, self.y, self.rx)
        rx = self.rx + [_value(v, self.x, self.y) for v in state[11]]
        if list(sm.rx) != rx:
            sm.rx = type(sm.rx)(rx)


_X, _Y = ("x", False, 0), ("y", False, 0)


def _shape_of(state, mkey: tuple) -> tuple:
    """The shape of the stretch from a loop state with the pins ``gpio_in`` and ``n_rx`` RX
    words, as long as X and Y are none of the values that would alias a shift register
    differently (:func:`trace.alias`): (shape, X's such values, Y's, whether X == Y is one);
    shape None when a shift register is a form of X or Y other than a copy."""
    _j, gpio_in, n_old = mkey
    n_rx = n_old + len(state[11])  # (the RX words before the stretch, and those its state pushed)
    danger_x, danger_y, x_eq_y, kept = set(), set(), False, []
    if state[7] is not None:  # (a pending exec may read any pin: its shape keeps them all, _shape)
        return None, danger_x, danger_y, x_eq_y, state[1], state[2], state[11]
    for reg in (state[3], state[5]):
        if type(reg) is int:
            if reg:
                danger_x.add(reg)
                danger_y.add(reg)
            kept.append(reg)
        elif reg == _X:  # (a copy of X: "x", or 0 when X is 0)
            danger_x.add(0)
            kept.append("x")
        elif reg == _Y:  # (a copy of Y: "y", 0 when Y is 0, "x" when X == Y)
            danger_y.add(0)
            x_eq_y = True
            kept.append("y")
        else:
            return None, danger_x, danger_y, x_eq_y, state[1], state[2], state[11]
    shape = trace.shape_of_state(state, kept[0], kept[1], n_rx, gpio_in, trace.MASK)  # (gpio_in: masked, turned)
    return shape, frozenset(danger_x), frozenset(danger_y), x_eq_y, state[1], state[2], state[11]


def _position(entry, since: int) -> int:
    r = since % entry.period
    j = bisect_left(entry.offsets, r)
    if j == len(entry.offsets) or entry.offsets[j] != r:
        raise ValueError("a state machine off its loop's step boundaries")
    return j


def walkers(block) -> list | None:
    """The block's active state machines as walkers, or None when one cannot be walked."""
    out = []
    for run in block.running.values():
        if not run.active:
            continue
        sm = run.sm
        if sm.set_count or sm.out_count or sm.side_count or not trace.plain(sm):
            return None
        if run.orbit and run.orbit_version == block.version:
            if run.table is None:
                return None
            if run.table[0].irq_flags != block.irq_flags:
                return None
            try:
                out.append(_Walker(run, False))
            except ValueError:
                return None
        else:
            out.append(_Walker(run, True))
    return out or None


def walk(block, t_us: int, changes, i: int = 0) -> int:
    """Take ``changes[i:]`` (then ``t_us``) as :meth:`PioBlock.advance` does, while every
    stretch is in the table: the index of the first change it did not take, the slow path
    going on from there (``len(changes)``: it took them all but not ``t_us``;
    ``len(changes) + 1``: ``t_us`` too)."""
    ws = walkers(block)
    if ws is None:
        return i
    n = len(changes)
    while i <= n:
        t = changes[i][0] if i < n else t_us
        for w in ws:
            c_t = -((-(t - w.t0) * w.mul) // w.den)
            if w.cycle >= c_t:
                continue
            if (w.pending and not w.resolve(block, c_t)) or c_t < w.anchor:  # (an instant before the loop:
                for other in ws:  # the slow path restores it from the stretch's states)
                    other.settle(block)
                return i
            w.go(c_t)
        if i < n:
            _t, gpio, level = changes[i]
            block.set_input(gpio, level)
            for w in ws:  # (those that read it: block.set_input)
                if w.reads >> gpio & 1:
                    w.pending = True
        i += 1
    for w in ws:
        w.settle(block)
    return n + 1
