# ruff: noqa: F821  (a PIO body's names exist only while rp2.asm_pio assembles it)
# The wheel encoders, each decoded by a PIO state machine: a 16-entry jump table indexed by
# the previous and the current A/B levels moves the count in X; each pass pushes X
# (dropped while the RX FIFO is full), and a read drains the FIFO and waits for a fresh one.
import rp2
from array import array
from machine import Pin


@rp2.asm_pio(in_shiftdir=rp2.PIO.SHIFT_LEFT, out_shiftdir=rp2.PIO.SHIFT_RIGHT, fifo_join=rp2.PIO.JOIN_RX)
def _quadrature():
    # index: (previous B A) << 2 | (B A now); A leads going forwards
    jmp("same")  # 00 -> 00
    jmp("fwd")  # 00 -> 01
    jmp("back")  # 00 -> 10
    jmp("same")  # 00 -> 11 (missed)
    jmp("back")  # 01 -> 00
    jmp("same")  # 01 -> 01
    jmp("same")  # 01 -> 10 (missed)
    jmp("fwd")  # 01 -> 11
    jmp("fwd")  # 10 -> 00
    jmp("same")  # 10 -> 01 (missed)
    jmp("same")  # 10 -> 10
    jmp("back")  # 10 -> 11
    jmp("same")  # 11 -> 00 (missed)
    jmp("back")  # 11 -> 01
    jmp("fwd")  # 11 -> 10
    jmp("same")  # 11 -> 11
    wrap_target()
    label("same")
    mov(isr, x)
    push(noblock)
    out(isr, 2)  # OSR's low bits: the previous levels (ISR empty after the push)
    in_(pins, 2)
    mov(osr, isr)
    mov(pc, isr)
    label("back")
    jmp(x_dec, "same")
    jmp("same")
    label("fwd")  # x + 1 as ~(~x - 1)
    mov(x, invert(x))
    jmp(x_dec, "fwd_done")
    label("fwd_done")
    mov(x, invert(x))
    wrap()
    nop()  # the program fills the PIO's 32 words, so it loads at address 0 (the table's)
    nop()
    nop()
    nop()
    nop()


class _Counter:
    def __init__(self, sm_id, pin_a, sign):
        Pin(pin_a, Pin.IN, Pin.PULL_UP)
        Pin(pin_a + 1, Pin.IN, Pin.PULL_UP)
        self.sm = rp2.StateMachine(sm_id, _quadrature, freq=25_000_000, in_base=Pin(pin_a))
        self.sign = sign
        self.word = array("i", [0])
        self.sm.active(1)

    def read(self):
        for _ in range(self.sm.rx_fifo()):
            self.sm.get()
        self.sm.get(self.word)  # ('i': the count's two's complement, signed)
        return self.sign * self.word[0]


class Encoders:
    def __init__(self):
        self.left = _Counter(0, 12, 1)
        self.right = _Counter(1, 8, 1)
        self.offsets = [0, 0]

    def get_counts(self, reset=False):
        left = self.left.read() - self.offsets[0]
        right = self.right.read() - self.offsets[1]
        if reset:
            self.offsets[0] += left
            self.offsets[1] += right
        return left, right
