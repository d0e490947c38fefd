# ruff: noqa: F821  (a PIO body's names exist only while rp2.asm_pio assembles it)
# PIO outputs as public RP2040 code writes them (MicroPython's examples/rp2: pio_pwm.py,
# pio_ws2812.py, pio_uart_tx.py): a PWM read back through a wire with time_pulse_us, a
# WS2812 strip beside one written by neopixel, a UART TX read by machine.UART.
import rp2
import time
from machine import UART, Pin, time_pulse_us

import neopixel


@rp2.asm_pio(sideset_init=rp2.PIO.OUT_LOW)
def pwm_prog():
    pull(noblock).side(0)
    mov(x, osr)
    mov(y, isr)
    label("pwmloop")
    jmp(x_not_y, "skip")
    nop().side(1)
    label("skip")
    jmp(y_dec, "pwmloop")


@rp2.asm_pio(sideset_init=rp2.PIO.OUT_LOW, out_shiftdir=rp2.PIO.SHIFT_LEFT, autopull=True, pull_thresh=24)
def ws2812():
    T1 = 2
    T2 = 5
    T3 = 3
    wrap_target()
    label("bitloop")
    out(x, 1).side(0)[T3 - 1]
    jmp(not_x, "do_zero").side(1)[T1 - 1]
    jmp("bitloop").side(1)[T2 - 1]
    label("do_zero")
    nop().side(0)[T2 - 1]
    wrap()


@rp2.asm_pio(sideset_init=rp2.PIO.OUT_HIGH, out_init=rp2.PIO.OUT_HIGH, out_shiftdir=rp2.PIO.SHIFT_RIGHT)
def uart_tx():
    pull().side(1)[7]
    set(x, 7).side(0)[7]
    label("bitloop")
    out(pins, 1)[6]
    jmp(x_dec, "bitloop")


# PWM: 1 MHz, a period of 2 * (100 + 1) + 4 cycles; duty count 30: high for 62 cycles
pwm = rp2.StateMachine(0, pwm_prog, freq=1_000_000, sideset_base=4)  # (a number: a Pin() here would be an input too)
pwm.put(100)
pwm.exec("pull()")
pwm.exec("mov(isr, osr)")
pwm.active(1)
pwm.put(30)
time.sleep_ms(5)
echo = Pin(5, Pin.IN)
print("R pwm_high_us", [time_pulse_us(echo, 1, 10000) for _ in range(3)])
print("R pwm_low_us", [time_pulse_us(echo, 0, 10000) for _ in range(3)])
pwm.active(0)  # (the line holds its level)

# WS2812: the same colours by PIO (GP12) and by neopixel (GP18)
colours = [(255, 0, 0), (0, 255, 0), (0, 0, 255), (16, 16, 16)]
ws = rp2.StateMachine(1, ws2812, freq=8_000_000, sideset_base=12)
ws.active(1)
for r, g, b in colours:
    ws.put((g << 16 | r << 8 | b) << 8)
np = neopixel.NeoPixel(Pin(18), 4)
for i, c in enumerate(colours):
    np[i] = c
np.write()
time.sleep_ms(20)

# UART TX at 115200 baud (8 PIO cycles a bit) into UART(0)
uart = UART(0, 115200)
tx = rp2.StateMachine(2, uart_tx, freq=8 * 115200, sideset_base=0, out_base=0)
tx.active(1)
for c in b"PIO says hi\n":
    tx.put(c)
time.sleep_ms(20)
print("R uart", uart.read())
print("R done", 1)
while True:
    time.sleep_ms(100)
