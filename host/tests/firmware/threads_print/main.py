# A second thread fills a list after a 1,050 us wait (Pololu's line_follower.py: its first
# PIO read of the line sensors); the main program sleeps 1 ms, computes (straight-line code:
# no clock read, no loop), prints, then reads the list, as that demo's redraw does.
import _thread
import time

line = []
t0 = time.ticks_us()


def worker():
    global line
    time.sleep_us(1050)
    line = [1, 2, 3]
    print("R worker_us", time.ticks_diff(time.ticks_us(), t0))


_thread.start_new_thread(worker, ())
time.sleep_ms(1)
a = abs(-1)
a = abs(-2)
a = abs(-3)
a = abs(-4)
a = abs(-5)
a = abs(-6)
a = abs(-7)
a = abs(-8)
a = abs(-9)
a = abs(-10)
print("R printed", True)
print("R seen", line[:])
time.sleep_ms(2)  # (the thread, if still waiting, prints meanwhile)
print("R main_us", time.ticks_diff(time.ticks_us(), t0))
