# ruff: noqa: F821  (a PIO body's names exist only while rp2.asm_pio assembles it)
# A FIFO level read after the firmware computed, with nothing of the board's called between:
# a program pushes a word every 128 us (every 32 cycles at 250 kHz); the CPU starts it, reads
# the RX level at once, computes, and reads it again, then the clock. With MCU time the
# second read is after the compute (docs/mcu-time.md), so the words pushed meanwhile are
# there; with compute free no time passed, and none are.
import rp2
import time


@rp2.asm_pio()
def ticker():
    wrap_target()
    mov(isr, invert(null))
    push(noblock)[30]
    wrap()


sm = rp2.StateMachine(0, ticker, freq=250_000)
t0 = time.ticks_us()
sm.active(1)
n0 = sm.rx_fifo()
x = 0
for i in range(20):
    x += i
n1 = sm.rx_fifo()
t1 = time.ticks_us()
words = [sm.get() for _ in range(n1)]
print("R levels", [n0, n1])
print("R elapsed_us", time.ticks_diff(t1, t0))
print("R words", words)
