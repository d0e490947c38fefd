# Two prints between two waits, each after some compute of its own (no clock read between).
import time

time.sleep_ms(1)
t0 = time.ticks_us()
x = 0
for i in range(300):
    x += i * i
print("R first", x)
for i in range(300):
    x -= i * i
print("R second", x)
print("R elapsed_us", time.ticks_diff(time.ticks_us(), t0))
time.sleep_ms(1)
