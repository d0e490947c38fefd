# The main program ends while a thread still runs (its loop sleeps 5 ms a pass).
import _thread
import time


def loop():
    while True:
        time.sleep_ms(5)


_thread.start_new_thread(loop, ())
time.sleep_ms(20)
print("R done", True)
