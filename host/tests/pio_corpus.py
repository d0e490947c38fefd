# ruff: noqa: F821  (a PIO body's names exist only while rp2.asm_pio assembles it)
"""PIO programs as public RP2040 MicroPython code writes them (the docs' and examples'
blink, PWM, WS2812, UART TX and RX, a servo, a quadrature decoder with a jump table) and
one that uses every instruction, directive and modifier, each with the same program in
pioasm text for Adafruit's independent assembler. Importable by MicroPython too (the
shim's assembler runs them there: host/tests/test_pio_asm.py)."""

OUT_LOW, OUT_HIGH, IN_LOW, IN_HIGH = 2, 3, 0, 1  # rp2.PIO's
SHIFT_LEFT, SHIFT_RIGHT = 0, 1


def blink():
    wrap_target()
    set(pins, 1)[31]
    nop()[31]
    nop()[31]
    set(pins, 0)[31]
    nop()[31]
    nop()[31]
    wrap()


BLINK = """
.wrap_target
    set pins, 1 [31]
    nop [31]
    nop [31]
    set pins, 0 [31]
    nop [31]
    nop [31]
.wrap
"""


def pwm():
    pull(noblock).side(0)
    mov(x, osr)
    mov(y, isr)
    label("pwmloop")
    jmp(x_not_y, "skip")
    nop().side(1)
    label("skip")
    jmp(y_dec, "pwmloop")


PWM = """
.side_set 1 opt
    pull noblock side 0
    mov x, osr
    mov y, isr
pwmloop:
    jmp x!=y skip
    nop side 1
skip:
    jmp y-- pwmloop
"""


def ws2812():
    wrap_target()
    label("bitloop")
    out(x, 1).side(0)[2]
    jmp(not_x, "do_zero").side(1)[1]
    jmp("bitloop").side(1)[4]
    label("do_zero")
    nop().side(0)[4]
    wrap()


WS2812 = """
.side_set 1
.wrap_target
bitloop:
    out x, 1 side 0 [2]
    jmp !x do_zero side 1 [1]
    jmp bitloop side 1 [4]
do_zero:
    nop side 0 [4]
.wrap
"""


def uart_tx():
    pull().side(1)[7]
    set(x, 7).side(0)[7]
    label("bitloop")
    out(pins, 1)[6]
    jmp(x_dec, "bitloop")


UART_TX = """
.side_set 1 opt
    pull side 1 [7]
    set x, 7 side 0 [7]
bitloop:
    out pins, 1 [6]
    jmp x-- bitloop
"""


def uart_rx():
    label("start")
    wait(0, pin, 0)
    set(x, 7)[10]
    label("bitloop")
    in_(pins, 1)
    jmp(x_dec, "bitloop")[6]
    jmp(pin, "good_stop")
    irq(block, 4)
    wait(1, pin, 0)
    jmp("start")
    label("good_stop")
    push(block)


UART_RX = """
start:
    wait 0 pin 0
    set x, 7 [10]
bitloop:
    in pins, 1
    jmp x-- bitloop [6]
    jmp pin good_stop
    irq wait 4
    wait 1 pin 0
    jmp start
good_stop:
    push block
"""


def servo():
    pull(noblock)  # a new pulse width, or X (the last one: a non-blocking pull of nothing)
    mov(x, osr)
    mov(y, x).side(1)  # the high time counted in Y: X keeps the width
    label("high")
    jmp(y_dec, "high")
    mov(y, isr).side(0)  # the low time, from ISR
    label("low")
    jmp(y_dec, "low")


SERVO = """
.side_set 1 opt
    pull noblock
    mov x, osr
    mov y, x side 1
high:
    jmp y-- high
    mov y, isr side 0
low:
    jmp y-- low
"""


def quadrature():
    # the jump table: (previous B A << 2 | B A now): A rising first counts up
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
    mov(isr, x)
    push(noblock)
    out(isr, 2)
    in_(pins, 2)
    mov(osr, isr)
    mov(pc, isr)
    label("down")
    jmp(x_dec, "update")
    jmp("update")
    label("up")
    mov(x, invert(x))
    jmp(x_dec, "up_done")
    label("up_done")
    mov(x, invert(x))
    wrap()
    # five words of padding: 32 in all, so the program sits at offset 0 and `mov pc` lands
    # on the table
    nop()
    nop()
    nop()
    nop()
    nop()


QUADRATURE = """
    jmp update
    jmp up
    jmp down
    jmp update
    jmp down
    jmp update
    jmp update
    jmp up
    jmp up
    jmp update
    jmp update
    jmp down
    jmp update
    jmp down
    jmp up
    jmp update
.wrap_target
update:
    mov isr, x
    push noblock
    out isr, 2
    in pins, 2
    mov osr, isr
    mov pc, isr
down:
    jmp x-- update
    jmp update
up:
    mov x, ~x
    jmp x-- up_done
up_done:
    mov x, ~x
.wrap
    nop
    nop
    nop
    nop
    nop
"""


def every_form():
    label("top")
    jmp("top")
    jmp(not_x, "top")
    jmp(x_dec, "end")
    jmp(not_y, "end")
    jmp(y_dec, "top")
    jmp(x_not_y, "top")
    jmp(pin, "top")
    jmp(not_osre, "end")
    label("end")
    wrap_target()
    wait(1, gpio, 5)
    wait(0, pin, 3)
    wait(1, irq, 2)
    wait(1, irq, rel(1))
    in_(pins, 32)
    in_(x, 1)
    in_(y, 7)
    in_(null, 3)
    in_(isr, 8)
    in_(osr, 16)
    out(pins, 4)
    out(x, 32)
    out(y, 2)
    out(null, 5)
    out(pindirs, 3)
    out(pc, 5)
    out(isr, 9)
    out(exec, 16)
    wrap()


def every_form_fifo():
    push()
    push(block)
    push(noblock)
    push(iffull)
    push(iffull, block)
    push(iffull, noblock)
    pull()
    pull(noblock)
    pull(ifempty)
    pull(ifempty, noblock)
    mov(pins, x)
    mov(x, y)
    mov(y, invert(x))
    mov(exec, y)
    mov(pc, osr)
    mov(isr, reverse(pins))
    mov(osr, null)
    wrap_target()
    mov(x, status)
    wrap()


def every_form_irq_set():
    label("top")
    irq(0)
    irq(block, 1)
    irq(clear, 2)
    irq(noblock, 3)
    irq(rel(1))
    irq(block, rel(2))
    set(pins, 31)
    set(x, 0)
    set(y, 17)
    set(pindirs, 3)
    nop()[7]
    word(0xA0E1)
    jmp(x_dec, "top")
    nop()[31]


EVERY_FORM = """
top:
    jmp top
    jmp !x top
    jmp x-- end
    jmp !y end
    jmp y-- top
    jmp x!=y top
    jmp pin top
    jmp !osre end
end:
.wrap_target
    wait 1 gpio 5
    wait 0 pin 3
    wait 1 irq 2
    wait 1 irq 1 rel
    in pins, 32
    in x, 1
    in y, 7
    in null, 3
    in isr, 8
    in osr, 16
    out pins, 4
    out x, 32
    out y, 2
    out null, 5
    out pindirs, 3
    out pc, 5
    out isr, 9
    out exec, 16
.wrap
"""

EVERY_FORM_FIFO = """
    push
    push block
    push noblock
    push iffull
    push iffull block
    push iffull noblock
    pull
    pull noblock
    pull ifempty
    pull ifempty noblock
    mov pins, x
    mov x, y
    mov y, ~x
    mov exec, y
    mov pc, osr
    mov isr, ::pins
    mov osr, null
.wrap_target
    mov x, status
.wrap
"""

EVERY_FORM_IRQ_SET = """
top:
    irq 0
    irq wait 1
    irq clear 2
    irq 3
    irq 1 rel
    irq wait 2 rel
    set pins, 31
    set x, 0
    set y, 17
    set pindirs, 3
    nop [7]
    mov osr, x  ; (word(0xA0E1): pioasm here has no .word)
    jmp x-- top
    nop [31]
"""


def side_pindirs():
    set(x, 3).side(2)
    label("loop")
    in_(pins, 1).side(1)[3]
    jmp(x_dec, "loop").side(3)[3]
    push().side(0)


SIDE_PINDIRS = """
.side_set 2 pindirs
    set x, 3 side 2
loop:
    in pins, 1 side 1 [3]
    jmp x-- loop side 3 [3]
    push side 0
"""

# name: (body, decorator settings, pioasm text)
CORPUS = {
    "blink": (blink, {"set_init": OUT_LOW}, BLINK),
    "pwm": (pwm, {"sideset_init": OUT_LOW}, PWM),
    "ws2812": (
        ws2812,
        {"sideset_init": OUT_LOW, "out_shiftdir": SHIFT_LEFT, "autopull": True, "pull_thresh": 24},
        WS2812,
    ),
    "uart_tx": (uart_tx, {"sideset_init": OUT_HIGH, "out_init": OUT_HIGH, "out_shiftdir": SHIFT_RIGHT}, UART_TX),
    "uart_rx": (uart_rx, {"in_shiftdir": SHIFT_RIGHT}, UART_RX),
    "servo": (servo, {"sideset_init": OUT_LOW}, SERVO),
    "quadrature": (quadrature, {"in_shiftdir": SHIFT_LEFT, "out_shiftdir": SHIFT_RIGHT}, QUADRATURE),
    "every_form": (
        every_form,
        {"out_init": (OUT_LOW,) * 4, "set_init": (OUT_LOW,) * 5, "autopush": True, "push_thresh": 8, "fifo_join": 2},
        EVERY_FORM,
    ),
    "every_form_fifo": (
        every_form_fifo,
        {"in_shiftdir": SHIFT_RIGHT, "pull_thresh": 0, "fifo_join": 1},
        EVERY_FORM_FIFO,
    ),
    "every_form_irq_set": (every_form_irq_set, {"set_init": (OUT_HIGH, IN_LOW, OUT_LOW)}, EVERY_FORM_IRQ_SET),
    "side_pindirs": (side_pindirs, {"sideset_init": (OUT_LOW, OUT_LOW), "side_pindir": True}, SIDE_PINDIRS),
}
