# Sleeping with the heap locked (code that proves its loop allocates nothing), then an
# error raised while it is still locked: its traceback must reach the host whole.
import micropython
import time

t0 = time.ticks_ms()
micropython.heap_lock()
for _ in range(3):
    time.sleep_ms(10)
micropython.heap_unlock()
print("R slept_ms", time.ticks_diff(time.ticks_ms(), t0))
micropython.heap_lock()
micropython.heap_lock()
x = [1, 2, 3]  # noqa: F841  allocates: MemoryError on a board, with its traceback
