# Two buttons' edges while the main program sleeps in short sleep_us calls (on an RP2040
# the whole of a sleep under 1 ms is the port's C busy loop): the soft handler's runs wait for
# the call to return, the hard one's run at the edge. Each run's instant is printed.
import time
from machine import Pin

soft_at = []
hard_at = []
t0 = time.ticks_us()


def soft(_pin):
    soft_at.append(time.ticks_diff(time.ticks_us(), t0))


def hard(_pin):
    hard_at.append(time.ticks_diff(time.ticks_us(), t0))


Pin(2, Pin.IN, Pin.PULL_UP).irq(soft, Pin.IRQ_FALLING | Pin.IRQ_RISING)
Pin(4, Pin.IN, Pin.PULL_UP).irq(hard, Pin.IRQ_FALLING | Pin.IRQ_RISING, hard=True)
while time.ticks_diff(time.ticks_us(), t0) < 1_000_000:
    time.sleep_us(120)
print("R soft", soft_at)
print("R hard", hard_at)
