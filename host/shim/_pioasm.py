# The PIO assembler of rp2.asm_pio (docs/shim.md, "PIO"): a program written in the
# RP2040 port's Python dialect (jmp, wait, in_, out, push, pull, mov, irq, set, nop, word,
# .side(), [delay], label, wrap_target, wrap) becomes the instruction words the port's
# assembler makes (RP2040 datasheet 3.4), and the program list the port's StateMachine
# takes: [words, offset in PIO0, offset in PIO1, EXECCTRL, SHIFTCTRL, out_init, set_init,
# sideset_init]. Written here from the datasheet; host/tests/test_pio_asm.py holds it to
# the port's own assembler and to Adafruit's pioasm, word for word.
# Runs in MicroPython (the shim) and in CPython (the host's emulator and the tests).
from array import array

SHIFT_LEFT = 0
JOIN_NONE = 0
DATA, OFFSET_PIO0, OFFSET_PIO1, EXECCTRL, SHIFTCTRL, OUT_PINS, SET_PINS, SIDESET_PINS = range(8)


class PIOASMError(Exception):
    pass


# Operands, as the port's assembler puts them in the body's globals.
_SOURCES = {
    "gpio": 0,
    "pins": 0,
    "x": 1,
    "y": 2,
    "null": 3,
    "pindirs": 4,
    "pc": 5,
    "status": 5,
    "isr": 6,
    "osr": 7,
    "exec": 8,
    "not_x": 1,
    "x_dec": 2,
    "not_y": 3,
    "y_dec": 4,
    "x_not_y": 5,
    "pin": 6,
    "not_osre": 7,
    "noblock": 0x01,
    "block": 0x21,
    "iffull": 0x40,
    "ifempty": 0x40,
    "clear": 0x40,
}


def _invert(src):
    return src | 0x08


def _reverse(src):
    return src | 0x10


def _rel(index):
    return index | 0x10


_OPERATORS = {"invert": _invert, "reverse": _reverse, "rel": _rel}
_INSTRUCTIONS = ("word", "nop", "jmp", "wait", "in_", "out", "push", "pull", "mov", "irq", "set")
_DIRECTIVES = ("wrap_target", "wrap", "label")


def _bit_count(n):
    if not 0 < n <= 32:
        raise PIOASMError("invalid bit count {}".format(n))
    return n & 0x1F


class Program:
    """One program being assembled: the body runs twice, once for its labels and counts,
    once to emit the words (a label may be used before it is placed)."""

    def __init__(
        self,
        out_init=None,
        set_init=None,
        sideset_init=None,
        side_pindir=False,
        in_shiftdir=SHIFT_LEFT,
        out_shiftdir=SHIFT_LEFT,
        autopush=False,
        autopull=False,
        push_thresh=32,
        pull_thresh=32,
        fifo_join=JOIN_NONE,
    ):
        shiftctrl = fifo_join << 30 | (pull_thresh & 0x1F) << 25 | (push_thresh & 0x1F) << 20
        shiftctrl |= out_shiftdir << 19 | in_shiftdir << 18 | autopull << 17 | autopush << 16
        self.prog = [array("H"), -1, -1, side_pindir << 29, shiftctrl, out_init, set_init, sideset_init]
        if sideset_init is None:
            self.side_bits = 0
        elif isinstance(sideset_init, int):
            self.side_bits = 1
        else:
            self.side_bits = len(sideset_init)
        self.labels = {}
        self.wrap_placed = False
        self.emitting = False
        self.side_opt = False
        self.delay_max = 31
        self.count = 0
        self.sides = 0

    def begin(self, emitting):
        """Start a pass; the second one knows whether side-set is optional (some
        instruction has none), which takes a bit from the delay field."""
        if emitting:
            if not self.wrap_placed and self.count:
                self.wrap()
            if self.side_bits:
                self.side_opt = self.sides != self.count
                if self.side_opt:
                    self.prog[EXECCTRL] |= 1 << 30
                    self.side_bits += 1
                self.delay_max = 31 >> self.side_bits
        self.emitting = emitting
        self.count = 0
        self.sides = 0

    # -- modifiers of the last instruction ------------------------------------------
    def __getitem__(self, cycles):
        return self.delay(cycles)

    def delay(self, cycles):
        if self.emitting:
            if cycles > self.delay_max:
                raise PIOASMError("delay too large")
            self.prog[DATA][-1] |= cycles << 8
        return self

    def side(self, value):
        self.sides += 1
        if self.emitting:
            if not self.side_bits:
                raise PIOASMError("no sideset")
            if value >= 1 << self.side_bits:
                raise PIOASMError("sideset too large")
            self.prog[DATA][-1] |= self.side_opt << 12 | value << (13 - self.side_bits)
        return self

    # -- directives -----------------------------------------------------------------
    def wrap_target(self):
        self.prog[EXECCTRL] |= self.count << 7

    def wrap(self):
        if not self.count:
            raise PIOASMError("wrap before any instruction")
        self.prog[EXECCTRL] |= (self.count - 1) << 12
        self.wrap_placed = True

    def label(self, name):
        if not self.emitting:
            if name in self.labels:
                raise PIOASMError("duplicate label {}".format(name))
            self.labels[name] = self.count

    # -- instructions -----------------------------------------------------------------
    def word(self, instr, label=None):
        self.count += 1
        if self.emitting:
            target = 0
            if label is not None:
                if label not in self.labels:
                    raise PIOASMError("unknown label {}".format(label))
                target = self.labels[label]
            self.prog[DATA].append(instr | target)
        return self

    def nop(self):
        return self.word(0xA042)  # mov y, y

    def jmp(self, cond, label=None):
        if label is None:
            cond, label = 0, cond
        return self.word(cond << 5, label)

    def wait(self, polarity, src, index):
        src = 1 if src == 6 else (0 if src == 0 else 2)  # gpio, pin, irq (anything else)
        return self.word(0x2000 | polarity << 7 | src << 5 | index)

    def in_(self, src, bits):
        return self.word(0x4000 | src << 5 | _bit_count(bits))

    def out(self, dest, bits):
        return self.word(0x6000 | (7 if dest == 8 else dest) << 5 | _bit_count(bits))

    def push(self, flag=0, flag2=0):
        flag |= flag2
        return self.word(0x8000 | ((flag | 0x20) if not flag & 1 else flag) & 0x60)

    def pull(self, flag=0, flag2=0):
        flag |= flag2
        return self.word(0x8080 | ((flag | 0x20) if not flag & 1 else flag) & 0x60)

    def mov(self, dest, src):
        return self.word(0xA000 | (4 if dest == 8 else dest) << 5 | src)

    def irq(self, mode, index=None):
        if index is None:
            mode, index = 0, mode
        return self.word(0xC000 | mode & 0x60 | index)

    def set(self, dest, value):
        return self.word(0xE000 | dest << 5 | value)

    def names(self, instructions=True):
        """The names the body sees: operands, and this program's instructions."""
        names = dict(_SOURCES)
        names.update(_OPERATORS)
        for name in _INSTRUCTIONS + (_DIRECTIVES if instructions else ()):
            names[name] = getattr(self, name)
        return names


def _restores():
    """ports/rp2/modules/rp2.py, asm_pio: from 1.28 its try/finally puts the body's module
    globals back when assembling raises; before, they were left as the PIO names alone."""
    import sys

    impl = sys.implementation  # (under CPython, as the host's tests load this file: put back)
    return impl.name != "micropython" or tuple(impl.version[:2]) >= (1, 28)


def asm_pio(**settings):
    """The decorator: the body, run with the PIO names as its globals (as on the port, it
    sees no other global while it runs), becomes the program list."""
    program = Program(**settings)

    def assemble(body):
        scope = body.__globals__
        saved = scope.copy()
        scope.clear()
        scope.update(program.names())
        done = False
        try:
            program.begin(False)
            body()
            program.begin(True)
            body()
            done = True
        finally:
            if done or _restores():
                scope.clear()
                scope.update(saved)
        return program.prog

    return assemble


def asm_pio_encode(instr, sideset_count, sideset_opt=False):
    """One instruction (source text) as its word; ``sideset_count`` counts the enable bit."""
    program = Program()
    program.side_bits = sideset_count
    program.side_opt = sideset_opt != 0
    program.delay_max = 31 >> (sideset_count + program.side_opt)
    program.emitting = True
    scope = program.names(instructions=False)
    scope["jmp"] = None  # (the port's does not encode jmp either)
    exec(instr, scope)
    if len(program.prog[DATA]) != 1:
        raise PIOASMError("expecting exactly 1 instruction")
    return program.prog[DATA][0]
