# Right: answers each ping with a pong after a pseudo-random delay, and stamps READY's
# edges in its IRQ handler (hard: an rp2 runs a soft one after a short sleep_us).
import time
from machine import UART, Pin

uart = UART(0, baudrate=115200)
ready = Pin(5, Pin.IN)
EDGES = 16  # (a ring the hard handler fills: it runs with the heap locked, so it allocates nothing)
edge_level, edge_at, n_in, n_out = bytearray(EDGES), [0] * EDGES, 0, 0


def on_edge(pin):
    global n_in
    i = n_in % EDGES
    edge_level[i] = pin.value()
    edge_at[i] = time.ticks_us()
    n_in += 1


ready.irq(on_edge, Pin.IRQ_RISING | Pin.IRQ_FALLING, hard=True)  # (at the edge, in any sleep)
seed = 777


def draw(n):
    global seed
    seed = (1103515245 * seed + 12345) & 0x7FFFFFFF
    return seed % n


buf = b""
while True:
    time.sleep_us(200 + draw(2500))
    while n_out < n_in:
        i = n_out % EDGES
        print("right edge", edge_level[i], "at", edge_at[i])
        n_out += 1
    if uart.any():
        buf += uart.read()
        while b"\n" in buf:
            line, buf = buf.split(b"\n", 1)
            print("right got", line.decode(), "at", time.ticks_us())
            uart.write(b"pong " + line[5:] + b"\n")
