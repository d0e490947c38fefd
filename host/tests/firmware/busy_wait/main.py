from time import ticks_diff, ticks_ms

t0 = ticks_ms()
n = 0
while ticks_diff(ticks_ms(), t0) < 100:
    n += 1
print("R waited_ms", ticks_diff(ticks_ms(), t0))
print("R polls", n)
