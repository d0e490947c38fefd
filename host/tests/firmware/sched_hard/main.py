# Edges during a time_pulse_us, then during a Timer callback that sleeps: a hard IRQ's
# handler runs at its edge (inside the call, preempting the callback); a soft one's waits
# for the call to return, or for the callback to end.
import time
from machine import Pin, Timer, time_pulse_us

echo = Pin(5, Pin.IN)
a = Pin(6, Pin.IN)
b = Pin(7, Pin.IN)
inside = False
hard, soft = [], []
hard_at, hard_inside, n_hard = [0] * 4, [False] * 4, 0  # (a hard handler allocates nothing: the heap is locked)
t0 = time.ticks_us()


def on_a(_p):
    global n_hard
    hard_at[n_hard] = time.ticks_diff(time.ticks_us(), t0)
    hard_inside[n_hard] = inside
    n_hard += 1


def on_b(_p):
    soft.append((time.ticks_diff(time.ticks_us(), t0), inside))


def slow(_t):
    global inside
    inside = True
    time.sleep_ms(10)
    inside = False


a.irq(on_a, Pin.IRQ_RISING, hard=True)
b.irq(on_b, Pin.IRQ_RISING)
inside = True
width = time_pulse_us(echo, 1, 50_000)
inside = False
Timer(-1, mode=Timer.ONE_SHOT, period=5, callback=slow)
time.sleep_ms(20)
print("R width", width)
print("R hard", [(hard_at[i], hard_inside[i]) for i in range(n_hard)])
print("R soft", soft)
