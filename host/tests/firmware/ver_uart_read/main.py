# UART reads at the first timeout (extmod/machine_uart.c, MicroPython 1.27): 3 bytes come
# back on the bench's looped UART (at 87, 174 and 260 us: 10 bits each at 115200 baud), a
# read of 5 with a 20 ms timeout asks for them. From 1.27 it returns after one call of the
# port's read; before, py/stream.c's loop (mp_stream_rw) calls it again, which waits one
# more timeout for the rest. The same for readinto (readinto1 from 1.27), after a pause
# that lets what a read left behind come in (drained).
import sys
import time
from machine import UART

u = UART(1, 115200, timeout=20)
print("R version", sys.implementation.version[:2])
u.write(b"abc")
t0 = time.ticks_us()
got = u.read(5)
print("R read", [got, time.ticks_diff(time.ticks_us(), t0)])
time.sleep_ms(30)
print("R left", u.read(u.any()) if u.any() else None)
buf = bytearray(5)
u.write(b"de")
t0 = time.ticks_us()
n = u.readinto(buf)
print("R readinto", [n, bytes(buf[:n]), time.ticks_diff(time.ticks_us(), t0)])
print("R readinto1", hasattr(u, "readinto1"))
