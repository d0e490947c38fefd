# Right: answers each ping with a pong after a pseudo-random delay, and stamps READY's
# edges in its IRQ handler (hard: an rp2 runs a soft one after a short sleep_us).
import time
from machine import UART, Pin

uart = UART(0, baudrate=115200)
ready = Pin(5, Pin.IN)
edges = []


def on_edge(pin):
    edges.append((pin.value(), time.ticks_us()))


ready.irq(on_edge, Pin.IRQ_RISING | Pin.IRQ_FALLING, hard=True)  # (at the edge, in any sleep)
seed = 777


def draw(n):
    global seed
    seed = (1103515245 * seed + 12345) & 0x7FFFFFFF
    return seed % n


buf = b""
while True:
    time.sleep_us(200 + draw(2500))
    while edges:
        level, t = edges.pop(0)
        print("right edge", level, "at", t)
    if uart.any():
        buf += uart.read()
        while b"\n" in buf:
            line, buf = buf.split(b"\n", 1)
            print("right got", line.decode(), "at", time.ticks_us())
            uart.write(b"pong " + line[5:] + b"\n")
