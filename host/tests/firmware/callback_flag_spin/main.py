# A soft Timer callback that waits for a flag a hard IRQ's handler sets, reading nothing of
# the board's meanwhile (`while not ready: pass`): on a board the handler interrupts the
# callback at its edge and the loop ends there. The callback reads the clock once it ends.
import time
from machine import Pin, Timer

a = Pin(6, Pin.IN)
t0 = time.ticks_us()
ready = False
waited = []


def on_a(_p):
    global ready
    ready = True


def wait_flag(_t):
    start = time.ticks_diff(time.ticks_us(), t0)
    while not ready:
        pass
    waited.append((start, time.ticks_diff(time.ticks_us(), t0)))


a.irq(on_a, Pin.IRQ_RISING, hard=True)
Timer(-1, mode=Timer.ONE_SHOT, period=10, callback=wait_flag)
time.sleep_ms(30)
print("R waited", waited)
