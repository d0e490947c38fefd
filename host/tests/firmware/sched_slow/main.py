# A Timer callback longer than its period (10 ms; it takes 15): the ticks that come due
# while it runs queue up to the scheduler's depth (the rest are lost, as on a board) and
# the main loop, which toggles the loop probe every 5 ms, gets no turn until the callback
# stops its timer and the queue has drained (the shim runs the queue to its end in a wait:
# docs/shim.md, "Where callbacks run").
import time
from machine import Pin, Timer

probe = Pin(15, Pin.OUT, value=0)
t0 = time.ticks_ms()
runs = []
stopped_at = []


def slow(t):
    runs.append(time.ticks_diff(time.ticks_ms(), t0))
    if len(runs) == 20:
        t.deinit()
        stopped_at.append(len(runs))
    time.sleep_ms(15)


Timer(0, mode=Timer.PERIODIC, period=10, callback=slow)
steps = []
while time.ticks_diff(time.ticks_ms(), t0) < 600:
    probe.toggle()
    steps.append(time.ticks_diff(time.ticks_ms(), t0))
    time.sleep_ms(5)
print("R runs", runs)
print("R stopped_at", stopped_at)
print("R steps", steps)
