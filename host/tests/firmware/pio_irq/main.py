# ruff: noqa: F821  (a PIO body's names exist only while rp2.asm_pio assembles it)
# PIO IRQ handlers as public RP2040 code writes them: a pulse counter that raises its IRQ
# on each rising edge (StateMachine.irq), and a program that raises irq(block, 1): its flag 1, waiting
# for the CPU to clear it, on each word it pushes (PIO(0).irq with IRQ_SM1).
import rp2
import time
from machine import PWM, Pin


@rp2.asm_pio()
def pulse_irq():
    wrap_target()
    wait(0, pin, 0)
    wait(1, pin, 0)
    irq(rel(0))
    wrap()


@rp2.asm_pio()
def tick_irq():
    wrap_target()
    set(x, 31)
    label("delay")
    jmp(x_dec, "delay")[31]
    mov(isr, invert(null))
    push(noblock)
    irq(block, 1)
    wrap()


src = PWM(Pin(4), freq=500, duty_u16=32768)  # into the wire, back on GP5
pulses = []
sm0 = rp2.StateMachine(0, pulse_irq, freq=1_000_000, in_base=Pin(5))
sm0.irq(lambda sm: pulses.append(time.ticks_us()))
sm0.active(1)
ticks = []
sm1 = rp2.StateMachine(1, tick_irq, freq=100_000)


def on_tick(pio):
    ticks.append((pio.irq().flags(), sm1.get()))


rp2.PIO(0).irq(on_tick, rp2.PIO.IRQ_SM1)
sm1.active(1)
time.sleep_ms(50)
assert sm0.irq().trigger() == 1  # (irq() with no argument leaves the handler armed)
time.sleep_ms(50)
sm0.active(0)
sm1.active(0)
print("R pulses", len(pulses))
print("R gaps_us", sorted(set((b - a) for a, b in zip(pulses, pulses[1:]))))
print("R ticks", len(ticks))
print("R tick_flags", sorted(set(f for f, _w in ticks)))
print("R tick_words", sorted(set(w for _f, w in ticks)))
print("R irq_flags", [sm0.irq().flags(), rp2.PIO(0).irq().trigger()])
print("R done", 1)
while True:
    time.sleep_ms(100)
