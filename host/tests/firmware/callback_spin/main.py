# A soft Timer callback that busy-waits, as public robot code does (a sonar read in a display
# Timer: `while echo.value() == 0: pass`): on a board the clock and the pins go on while it
# runs. A hard IRQ's handler on another pin runs at its edge inside the callback's wait; a
# soft one's waits for the callback to return (the scheduler is locked meanwhile). A second
# callback waits 500 us on the clock alone.
import time
from machine import Pin, Timer

echo = Pin(5, Pin.IN)
a = Pin(6, Pin.IN)
b = Pin(7, Pin.IN)
t0 = time.ticks_us()
inside = False
read = []
hard_at = [0] * 2  # (a hard handler allocates nothing: the heap is locked)
n_hard = 0
soft = []
delay = []


def now():
    return time.ticks_diff(time.ticks_us(), t0)


def sonar(_t):
    global inside
    inside = True
    start = now()
    while echo.value() == 0:
        pass
    rose = now()
    while echo.value() == 1:
        pass
    read.append((start, rose, now()))
    inside = False


def wait_500(_t):
    start = time.ticks_us()
    while time.ticks_diff(time.ticks_us(), start) < 500:
        pass
    delay.append((time.ticks_diff(start, t0), now()))


def on_a(_p):
    global n_hard
    if n_hard < 2:
        hard_at[n_hard] = time.ticks_diff(time.ticks_us(), t0)
    n_hard += 1


def on_b(_p):
    soft.append((now(), inside))


a.irq(on_a, Pin.IRQ_RISING, hard=True)
b.irq(on_b, Pin.IRQ_RISING)
Timer(-1, mode=Timer.ONE_SHOT, period=10, callback=sonar)
Timer(-1, mode=Timer.ONE_SHOT, period=30, callback=wait_500)
time.sleep_ms(40)
print("R read", read)
print("R hard", hard_at[:n_hard])
print("R soft", soft)
print("R delay", delay)
