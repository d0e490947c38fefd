# UART reads at the first timeout (extmod/machine_uart.c, MicroPython 1.27): 3 bytes come
# back on the bench's looped UART, a read of 5 with a 20 ms timeout gets them. From 1.27 it
# returns at that timeout; before, py/stream.c's loop (mp_stream_rw) asks the port again
# and waits a second timeout for the rest. readinto the same (readinto1 from 1.27).
import sys
import time
from machine import UART

u = UART(1, 115200, timeout=20)
print("R version", sys.implementation.version[:2])
u.write(b"abc")
t0 = time.ticks_ms()
got = u.read(5)
print("R read", [got, time.ticks_diff(time.ticks_ms(), t0)])
buf = bytearray(5)
u.write(b"de")
t0 = time.ticks_ms()
n = u.readinto(buf)
print("R readinto", [n, bytes(buf[:n]), time.ticks_diff(time.ticks_ms(), t0)])
print("R readinto1", hasattr(u, "readinto1"))
