# ruff: noqa: F821  (a PIO body's names exist only while rp2.asm_pio assembles it)
# A fast output looped back to an input with no IRQ while the firmware sleeps: a PIO PWM
# (MicroPython's examples/rp2/pio_pwm.py) and a machine.PWM, each on a wire to a Pin read
# only now and then; a UART is open (the plant goes in chunks while bytes may flow).
import rp2
import time
from machine import PWM, UART, Pin


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


uart = UART(0, 115200)
pio_echo, pwm_echo = Pin(5, Pin.IN), Pin(7, Pin.IN)
pwm = rp2.StateMachine(0, pwm_prog, freq=1_000_000, sideset_base=4)  # ~4.85 kHz
pwm.put(100)
pwm.exec("pull()")
pwm.exec("mov(isr, osr)")
pwm.active(1)
pwm.put(30)
hw = PWM(Pin(6), freq=20_000, duty_u16=32768)
seen = set()
for _ in range(10):
    time.sleep_ms(40)
    seen.add((pio_echo.value(), pwm_echo.value()))
print("R sleeps", 10)
print("R levels_seen", len(seen))
print("R done", 1)
while True:
    time.sleep_ms(100)
