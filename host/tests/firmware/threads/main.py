# Two threads as a kit's demos use them (Pololu's line_follower.py: a fast loop on the second
# core, the display and the buttons on the first), on one virtual clock.
import _thread
import time
from machine import Pin

led = Pin(2, Pin.OUT)
log = []
lock = _thread.allocate_lock()
state = {"passes": 0, "stop": False, "seen": []}


def sleeper():
    # the second thread sleeps 15 ms a pass: its wakes interleave with the main program's
    for _ in range(4):
        time.sleep_ms(15)
        log.append(("t", time.ticks_ms()))


def busy():
    # a loop that never sleeps: reads the clock, toggles a pin, counts
    while not state["stop"]:
        led.value(state["passes"] % 2)
        state["passes"] += 1
        time.ticks_us()


def holder():
    with lock:
        log.append(("held", time.ticks_ms()))
        time.sleep_ms(20)
    log.append(("let go", time.ticks_ms()))


def fails():
    raise ValueError("from the thread")


t0 = time.ticks_ms()
_thread.start_new_thread(sleeper, ())
for _ in range(6):
    time.sleep_ms(10)
    log.append(("m", time.ticks_ms()))
print("R interleaved", [(who, time.ticks_diff(t, t0)) for who, t in log])

log.clear()
_thread.start_new_thread(busy, ())
for _ in range(5):
    time.sleep_ms(1)
    state["seen"].append(state["passes"])
state["stop"] = True
time.sleep_ms(1)
print("R busy_seen", state["seen"])

t0 = time.ticks_ms()
_thread.start_new_thread(holder, ())
time.sleep_ms(1)
lock.acquire()
log.append(("main got it", time.ticks_ms()))
lock.release()
print("R lock", [(who, time.ticks_diff(t, t0)) for who, t in log])

_thread.start_new_thread(fails, ())
time.sleep_ms(5)
print("R after_failure", True)
