"""One PIO state machine, cycle by cycle (RP2040 datasheet 3.4, 3.5).

:class:`StateMachine` executes the instruction at its program counter in one cycle, or
stalls on it (a ``wait`` not met, a blocking ``push``/``pull`` on a full/empty FIFO, an
``irq wait`` not yet cleared, an ``out`` with autopull and no data); a delay adds idle
cycles after an instruction that completed. Side-set is applied at an instruction's first
cycle, stalled or not. The configuration is the hardware's own registers (EXECCTRL,
SHIFTCTRL, PINCTRL), as the shim computes them from ``StateMachine.init``'s arguments.

Not modelled: the two-cycle input synchroniser, the fractional clock divider's jitter
(one cycle is exactly ``1/freq``), ``OUT_STICKY``/``INLINE_OUT_EN``, the background
autopull between instructions (the refill happens at the ``out`` that needs it).
"""

import copy
from collections import deque
from dataclasses import dataclass

MASK = 0xFFFFFFFF


class PioStall(Exception):
    """An instruction cannot complete this cycle (raised inside one step only)."""


@dataclass(frozen=True)
class PioConfig:
    """A state machine's registers, decoded."""

    execctrl: int
    shiftctrl: int
    pinctrl: int
    div256: int  # the clock divider, 16.8 fixed point: one cycle is div256 / 256 system clocks
    pc: int  # the first instruction (the program's offset in the PIO's memory)

    SYS_HZ = 125_000_000

    @property
    def freq_hz(self) -> float:
        return self.SYS_HZ * 256 / self.div256

    @property
    def wrap_top(self):
        return self.execctrl >> 12 & 0x1F

    @property
    def wrap_bottom(self):
        return self.execctrl >> 7 & 0x1F


def _bits(n):
    return MASK if n >= 32 else (1 << n) - 1


def _reverse32(v):
    return int(f"{v:032b}"[::-1], 2)


class StateMachine:
    """Registers, shift counters, FIFOs and the pins it drives; :meth:`step` runs a cycle."""

    def __init__(self, block, sm_id: int, config: PioConfig):
        self.block = block
        self.sm_id = sm_id
        self.read_mask = MASK  # the GPIOs its program can read (read_mask(), set by the block)
        self.key_rot = None  # the pins in its shapes turned by in_base (relative(): shared tables), or not
        self.configure(config)
        self.restart()
        self.tx = deque()
        self.rx = deque()

    def __deepcopy__(self, memo):
        """Its fields are numbers, the frozen config and the two FIFOs (a look-ahead's copy,
        often: :meth:`PioBlock.probe`, ``host/rig/hardware/pio_out.py``)."""
        twin = StateMachine.__new__(StateMachine)
        memo[id(self)] = twin
        twin.__dict__.update(self.__dict__)
        twin.block = copy.deepcopy(self.block, memo)
        twin.tx, twin.rx = deque(self.tx), deque(self.rx)
        if type(self.x) is not int or type(self.y) is not int or type(self.isr) is not int or type(self.osr) is not int:
            for name in ("x", "y", "isr", "osr"):
                setattr(twin, name, copy.deepcopy(getattr(self, name), memo))
        return twin

    def configure(self, config: PioConfig) -> None:
        c = config
        self.config = c
        self.side_en = bool(c.execctrl >> 30 & 1)
        self.side_pindir = bool(c.execctrl >> 29 & 1)
        self.jmp_pin = c.execctrl >> 24 & 0x1F
        self.wrap_top, self.wrap_bottom = c.wrap_top, c.wrap_bottom
        self.status_sel, self.status_n = c.execctrl >> 4 & 1, c.execctrl & 0xF
        join_rx, join_tx = c.shiftctrl >> 31 & 1, c.shiftctrl >> 30 & 1
        self.rx_depth = 8 if join_rx else (0 if join_tx else 4)
        self.tx_depth = 8 if join_tx else (0 if join_rx else 4)
        self.pull_thresh = (c.shiftctrl >> 25 & 0x1F) or 32
        self.push_thresh = (c.shiftctrl >> 20 & 0x1F) or 32
        self.out_right, self.in_right = bool(c.shiftctrl >> 19 & 1), bool(c.shiftctrl >> 18 & 1)
        self.autopull, self.autopush = bool(c.shiftctrl >> 17 & 1), bool(c.shiftctrl >> 16 & 1)
        self.side_count = c.pinctrl >> 29 & 7  # (with the enable bit)
        self.set_count = c.pinctrl >> 26 & 7
        self.out_count = c.pinctrl >> 20 & 0x3F
        self.in_base = c.pinctrl >> 15 & 0x1F
        self.side_base = c.pinctrl >> 10 & 0x1F
        self.set_base = c.pinctrl >> 5 & 0x1F
        self.out_base = c.pinctrl & 0x1F
        self.delay_bits = 5 - self.side_count
        self.delay_mask = (1 << self.delay_bits) - 1
        self.side_bits = self.side_count - self.side_en  # (value bits)

    def restart(self) -> None:
        """SM_RESTART: registers, shift counters and delay cleared (FIFOs kept)."""
        self.pc = self.config.pc
        self.x = self.y = self.isr = self.osr = 0
        self.isr_n = 0
        self.osr_n = 32  # the OSR starts empty
        self.delay = 0
        self.pending_exec = None  # an instruction from `mov exec`, `out exec` or sm.exec()
        self.irq_waiting = False  # an `irq wait` raised its flag and waits for it to clear

    # -- helpers ---------------------------------------------------------------------
    def key(self) -> tuple:
        """All that decides what it does next (with the pins it reads)."""
        return (
            self.pc,
            self.x,
            self.y,
            self.isr,
            self.isr_n,
            self.osr,
            self.osr_n,
            tuple(self.rx),
            tuple(self.tx),
            self.pending_exec,
            self.irq_waiting,
            self.block.irq_flags,
        )

    def pins_in(self) -> int:
        """The 32 GPIO inputs rotated so that ``in_base`` is bit 0."""
        g, b = self.block.gpio_in, self.in_base
        return ((g >> b) | (g << (32 - b))) & MASK

    def _drive(self, base: int, count: int, value: int, dirs: bool = False) -> None:
        for i in range(count):
            self.block.drive((base + i) & 31, value >> i & 1, dirs)

    def _side_set(self, word: int) -> None:
        field = word >> 8 & 0x1F
        if self.side_en and not field & 0x10:
            return
        value = (field >> self.delay_bits) & _bits(self.side_bits)
        self._drive(self.side_base, self.side_bits, value, self.side_pindir)

    # -- a cycle ---------------------------------------------------------------------
    def step(self) -> int:
        """Run one instruction (or one of its stalled cycles); the cycles it took."""
        word = executed = self.pending_exec
        if word is not None:
            self.pending_exec = None
            pc_next = self.pc
        else:
            word = self.block.memory[self.pc]
            pc_next = self.wrap_bottom if self.pc == self.wrap_top else (self.pc + 1) & 31
        if self.side_count:
            self._side_set(word)
        try:
            jump = _EXECUTE[word >> 13](self, word)
        except PioStall:
            if executed is not None:
                self.pending_exec = executed  # (a stalled exec'd instruction runs again)
            return 1
        self.pc = pc_next if jump is None else jump
        return 1 + ((word >> 8) & self.delay_mask)

    # -- instructions (each returns the pc it jumps to, or None) --------------------
    def _jmp(self, w):
        cond, target = w >> 5 & 7, w & 0x1F
        if cond == 0:
            ok = True
        elif cond == 1:
            ok = self.x == 0
        elif cond == 2:
            ok, self.x = self.x != 0, (self.x - 1) & MASK
        elif cond == 3:
            ok = self.y == 0
        elif cond == 4:
            ok, self.y = self.y != 0, (self.y - 1) & MASK
        elif cond == 5:
            ok = self.x != self.y
        elif cond == 6:
            ok = bool(self.block.gpio_in >> self.jmp_pin & 1)
        else:
            ok = self.osr_n < self.pull_thresh
        return target if ok else None

    def _wait(self, w):
        polarity, source, index = w >> 7 & 1, w >> 5 & 3, w & 0x1F
        if source == 0:
            level = self.block.gpio_in >> index & 1
        elif source == 1:
            level = self.block.gpio_in >> ((self.in_base + index) & 31) & 1
        else:
            flag = self._irq_index(index)
            level = self.block.irq_flags >> flag & 1
            if level == polarity and polarity:
                self.block.irq_flags &= ~(1 << flag)
        if level != polarity:
            raise PioStall
        return None

    def _in(self, w):
        source, n = w >> 5 & 7, (w & 0x1F) or 32
        if self.autopush and self.isr_n >= self.push_thresh:
            self._push_now(block=True)
        data = self._source(source) & _bits(n)
        if self.in_right:
            self.isr = ((self.isr >> n) | (data << (32 - n))) & MASK if n < 32 else data
        else:
            self.isr = ((self.isr << n) | data) & MASK if n < 32 else data
        self.isr_n = min(32, self.isr_n + n)
        if self.autopush and self.isr_n >= self.push_thresh and len(self.rx) < self.rx_depth:
            self._push_now(block=True)
        return None

    def _out(self, w):
        dest, n = w >> 5 & 7, (w & 0x1F) or 32
        if self.autopull and self.osr_n >= self.pull_thresh:
            if not self.tx:
                raise PioStall
            self.osr, self.osr_n = self.tx.popleft(), 0
        if self.out_right:
            data = self.osr & _bits(n)
            self.osr = self.osr >> n if n < 32 else 0
        else:
            data = self.osr >> (32 - n) if n < 32 else self.osr
            self.osr = (self.osr << n) & MASK if n < 32 else 0
        self.osr_n = min(32, self.osr_n + n)
        return _OUT_DEST[dest](self, data, n)

    def _push_pull(self, w):
        if_flag, block = w >> 6 & 1, w >> 5 & 1
        if w & 0x80:  # pull
            if if_flag and self.osr_n < self.pull_thresh:
                return None
            if not self.tx:
                if block:
                    raise PioStall
                self.osr, self.osr_n = self.x, 0
            else:
                self.osr, self.osr_n = self.tx.popleft(), 0
            return None
        if if_flag and self.isr_n < self.push_thresh:
            return None
        self._push_now(block)
        return None

    def _push_now(self, block):
        if len(self.rx) >= self.rx_depth:
            if block:
                raise PioStall
        else:
            self.rx.append(self.isr)
        self.isr, self.isr_n = 0, 0  # (a non-blocking push to a full FIFO loses the ISR)

    def _mov(self, w):
        dest, op, source = w >> 5 & 7, w >> 3 & 3, w & 7
        value = self._source(source)
        if op == 1:
            value = ~value & MASK
        elif op == 2:
            value = _reverse32(value)
        return _MOV_DEST[dest](self, value)

    def _irq(self, w):
        clear, wait, flag = w >> 6 & 1, w >> 5 & 1, self._irq_index(w & 0x1F)
        block = self.block
        if clear:
            block.irq_flags &= ~(1 << flag)
            return None
        if self.irq_waiting:
            if block.irq_flags >> flag & 1:
                raise PioStall
            self.irq_waiting = False
            return None
        block.raise_irq(flag, self.sm_id)
        if wait:
            self.irq_waiting = True
            raise PioStall
        return None

    def _set(self, w):
        dest, data = w >> 5 & 7, w & 0x1F
        if dest == 0:
            self._drive(self.set_base, self.set_count, data)
        elif dest == 1:
            self.x = data
        elif dest == 2:
            self.y = data
        elif dest == 4:
            self._drive(self.set_base, self.set_count, data, True)
        return None

    def _irq_index(self, index):
        if index & 0x10:
            return (index & 4) | ((index + self.sm_id) & 3)
        return index & 7

    def _source(self, source):
        if source == 0:
            return self.pins_in()
        if source == 1:
            return self.x
        if source == 2:
            return self.y
        if source == 5:  # STATUS
            level = len(self.rx) if self.status_sel else len(self.tx)
            return MASK if level < self.status_n else 0
        if source == 6:
            return self.isr
        if source == 7:
            return self.osr
        return 0


def read_mask(memory: list, sm: StateMachine) -> int:
    """The GPIOs the instructions in ``memory`` can read when ``sm`` runs them (``wait gpio``,
    ``wait pin``, ``jmp pin``, ``in pins``; all of them for a ``mov`` from the pins or a
    program that can execute a word of data, ``out exec`` or ``mov exec``): a pin outside it
    changes nothing the state machine does."""
    mask = 0
    for word in memory:
        op = word >> 13
        if op == 0 and word >> 5 & 7 == 6:
            mask |= 1 << sm.jmp_pin
        elif op == 1 and word >> 5 & 3 == 0:
            mask |= 1 << (word & 0x1F)
        elif op == 1 and word >> 5 & 3 == 1:
            mask |= 1 << ((sm.in_base + (word & 0x1F)) & 31)
        elif op == 2 and word >> 5 & 7 == 0:
            bits = _bits((word & 0x1F) or 32)
            mask |= ((bits << sm.in_base) | (bits >> (32 - sm.in_base))) & MASK
        elif (op == 5 and word & 7 == 0) or (op == 5 and word >> 5 & 7 == 4) or (op == 3 and word >> 5 & 7 == 7):
            return MASK
    return mask


def relative(memory: list) -> bool:
    """A program whose state machine reads the pins only through ``in_base`` (``in pins``,
    ``wait pin``, ``mov`` from the pins; no ``wait gpio``, no ``jmp pin``) and touches nothing
    outside itself (:func:`block.pure`): two state machines of a block that run it with the
    same registers but ``in_base`` do the same with the same pins counted from ``in_base``,
    so they can share their stretch tables (their shapes' pins turned by ``in_base``)."""
    for word in memory:
        op = word >> 13
        if (op == 0 and word >> 5 & 7 == 6) or (op == 1 and word >> 5 & 3 != 1):
            return False
    return True


def _out_pins(sm, data, n):
    sm._drive(sm.out_base, sm.out_count, data)


def _out_dirs(sm, data, n):
    sm._drive(sm.out_base, sm.out_count, data, True)


def _out_isr(sm, data, n):
    sm.isr, sm.isr_n = data, n


def _out_exec(sm, data, n):
    sm.pending_exec = data & 0xFFFF


def _set_attr(name):
    def put(sm, value, n=0):
        setattr(sm, name, value)

    return put


def _nothing(sm, value, n=0):
    return None


def _to_pc(sm, value, n=0):
    return value & 0x1F


_OUT_DEST = [_out_pins, _set_attr("x"), _set_attr("y"), _nothing, _out_dirs, _to_pc, _out_isr, _out_exec]


def _mov_pins(sm, value):
    sm._drive(sm.out_base, sm.out_count, value)


def _mov_exec(sm, value):
    sm.pending_exec = value & 0xFFFF


def _mov_isr(sm, value):
    sm.isr, sm.isr_n = value, 0


def _mov_osr(sm, value):
    sm.osr, sm.osr_n = value, 0


_MOV_DEST = [_mov_pins, _set_attr("x"), _set_attr("y"), _nothing, _mov_exec, _to_pc, _mov_isr, _mov_osr]
_EXECUTE = [
    StateMachine._jmp,
    StateMachine._wait,
    StateMachine._in,
    StateMachine._out,
    StateMachine._push_pull,
    StateMachine._mov,
    StateMachine._irq,
    StateMachine._set,
]
