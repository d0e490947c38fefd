# ruff: noqa: F821  (a PIO body's names exist only while rp2.asm_pio assembles it)
# The quadrature decoder of examples/pico_pio_bot (the pico-examples program's shape): the
# count in X, pushed each pass (dropped while the RX FIFO is full).
import rp2


@rp2.asm_pio(in_shiftdir=rp2.PIO.SHIFT_LEFT, out_shiftdir=rp2.PIO.SHIFT_RIGHT)
def quadrature():
    # OSR keeps the last B A; ISR gets (last B A) << 2 | (B A now), and `mov pc, isr`
    # jumps into this table, which must start at address 0 (see the padding below)
    jmp("update")  # 00 -> 00
    jmp("up")  # 00 -> 01
    jmp("down")  # 00 -> 10
    jmp("update")  # 00 -> 11
    jmp("down")  # 01 -> 00
    jmp("update")  # 01 -> 01
    jmp("update")  # 01 -> 10
    jmp("up")  # 01 -> 11
    jmp("up")  # 10 -> 00
    jmp("update")  # 10 -> 01
    jmp("update")  # 10 -> 10
    jmp("down")  # 10 -> 11
    jmp("update")  # 11 -> 00
    jmp("down")  # 11 -> 01
    jmp("up")  # 11 -> 10
    jmp("update")  # 11 -> 11
    wrap_target()
    label("update")
    mov(isr, x)  # the count, to the RX FIFO (dropped while the FIFO is full)
    push(noblock)
    out(isr, 2)
    in_(pins, 2)
    mov(osr, isr)
    mov(pc, isr)
    label("down")
    jmp(x_dec, "update")
    jmp("update")
    label("up")  # x + 1 is ~(~x - 1)
    mov(x, invert(x))
    jmp(x_dec, "up_done")
    label("up_done")
    mov(x, invert(x))
    wrap()
    # 32 words in all: the PIO's whole memory, so the program is loaded at address 0
    nop()
    nop()
    nop()
    nop()
    nop()
