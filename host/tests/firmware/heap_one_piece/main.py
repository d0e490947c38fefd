# The biggest piece of its heap a fresh firmware can take at once: on a board the heap is
# one piece at power-on, so nearly all of gc.mem_free() (found by halving, each try after
# a collect).
import gc

free = low = high = n = 0  # (each global's slot made before the first try)
piece = None
gc.collect()
free = high = gc.mem_free()
while high - low > 64:
    n = (low + high) // 2
    gc.collect()
    try:
        piece = bytearray(n)
        low = n
    except MemoryError:
        high = n
    piece = None
print("R free", free)
print("R piece", low)
