# Prints under micropython.heap_lock() after compute (locals only: a new global could grow
# the module's dict, which a board's locked heap refuses too).
import micropython
import time


def run():
    micropython.heap_lock()
    x = 0
    for i in range(200):
        x += i
    print("R locked", x)
    print("R again", 3)
    for i in range(400):  # (a longer stretch, then a wait under the lock: a record stretch's code)
        x -= i
    time.sleep_ms(1)
    print("R after_wait", x)
    micropython.heap_unlock()


time.sleep_ms(1)
run()
print("R done", True)
