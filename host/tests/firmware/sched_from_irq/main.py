# A pin IRQ's soft handler hands its work on with micropython.schedule (picozero's Button
# does: its callbacks run so), while the main program sleeps: the sleep's next pass runs
# the job at the edge's instant, each edge's in turn.
import micropython
import time
from machine import Pin

edges, jobs = [], []


def job(level):
    jobs.append((level, time.ticks_us()))


def edge(pin):
    edges.append((pin.value(), time.ticks_us()))
    micropython.schedule(job, pin.value())


button = Pin(23, Pin.IN, Pin.PULL_UP)
button.irq(edge, Pin.IRQ_RISING | Pin.IRQ_FALLING)
time.sleep_ms(100)
print("R edges", edges)
print("R jobs", jobs)
