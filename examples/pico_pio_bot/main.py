# ruff: noqa: F821  (a PIO body's names exist only while rp2.asm_pio assembles it)
# A two-wheel robot on a Raspberry Pi Pico that counts its wheel encoders with PIO, as the
# RP2040 robot kits' libraries do: a quadrature decoder with a jump table runs in a state
# machine per wheel and keeps the count in its X register; the CPU only reads the count
# from the RX FIFO. It drives a square (ahead 1500 counts, turn 420, four times), stops and
# prints both counts. Plain MicroPython, as it goes on the board: test_pico_pio_bot.py runs
# it against a simulated robot whose encoders make the edges.
import time

import rp2
from machine import PWM, Pin

PWMA, AIN1, AIN2 = 16, 17, 18
PWMB, BIN1, BIN2 = 21, 20, 19
STBY = 22
ENC_LA, ENC_RA = 2, 4  # B is the next pin (GP3, GP5): the decoder reads two pins from in_base

AHEAD_COUNTS = 1500
TURN_COUNTS = 420
SPEED = 0.5


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


class PioEncoder:
    def __init__(self, sm_id, pin_a, sign=1):
        self.sm = rp2.StateMachine(sm_id, quadrature, freq=10_000_000, in_base=Pin(pin_a))
        self.sign = sign
        self.sm.active(1)

    def count(self):
        # the FIFO holds old counts: drain it, then the next one is fresh
        for _ in range(self.sm.rx_fifo()):
            self.sm.get()
        n = self.sm.get()
        return self.sign * (n - (1 << 32) if n & 0x80000000 else n)


class Motor:
    def __init__(self, pwm, in1, in2):
        self.pwm = PWM(Pin(pwm))
        self.pwm.freq(20000)
        self.in1 = Pin(in1, Pin.OUT)
        self.in2 = Pin(in2, Pin.OUT)

    def speed(self, s):
        self.in1.value(1 if s > 0 else 0)
        self.in2.value(1 if s < 0 else 0)
        self.pwm.duty_u16(int(min(abs(s), 1.0) * 65535))


def move(left_speed, right_speed, counts):
    """Drive until the left wheel has turned `counts` further, either way."""
    start = enc_l.count()
    left.speed(left_speed)
    right.speed(right_speed)
    while abs(enc_l.count() - start) < counts:
        time.sleep_ms(5)
    left.speed(0)
    right.speed(0)
    time.sleep_ms(200)


left = Motor(PWMA, AIN1, AIN2)
right = Motor(PWMB, BIN1, BIN2)
Pin(STBY, Pin.OUT, value=1)
enc_l = PioEncoder(0, ENC_LA)
enc_r = PioEncoder(1, ENC_RA)

print("pio_bot: start", enc_l.count(), enc_r.count())
for side in range(4):
    move(SPEED, SPEED, AHEAD_COUNTS)
    print("pio_bot: side", side, enc_l.count(), enc_r.count())
    move(-SPEED, SPEED, TURN_COUNTS)
print("pio_bot: done", enc_l.count(), enc_r.count())
while True:
    time.sleep_ms(100)
