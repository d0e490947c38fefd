# What a board lets a hard IRQ's handler do with its heap locked (shared/runtime/mpirq.c,
# mp_irq_handler): read its pin and the clock, drive another pin and a PWM, ask its IRQ's
# flags, store into buffers made before, count, call a bound method, schedule a soft callback.
import micropython
import time
from machine import PWM, Pin

N = 8
at = [0] * N
flags = bytearray(N)
scheduled = [0]


def later(n):  # (soft: runs after the handler, where allocating is fine)
    scheduled[0] += n


class Counter:
    def __init__(self, pin):
        self.n = 0
        self.out = Pin(2, Pin.OUT)
        self.pwm = PWM(Pin(4), freq=1000, duty_u16=0)
        pin.irq(self.edge, Pin.IRQ_RISING | Pin.IRQ_FALLING, hard=True)

    def edge(self, pin):
        i = self.n
        if i < N:
            at[i] = time.ticks_diff(time.ticks_us(), t0)
            flags[i] = pin.irq().flags()
        self.out.value(pin.value())
        self.pwm.duty_u16(1000 * (i + 1))
        micropython.schedule(later, 1)
        self.n = i + 1


t0 = time.ticks_us()
counter = Counter(Pin(5, Pin.IN))
time.sleep_ms(20)
print("R edges", counter.n)
print("R at", at[: counter.n])
print("R flags", list(flags[: counter.n]))
print("R scheduled", scheduled[0])
