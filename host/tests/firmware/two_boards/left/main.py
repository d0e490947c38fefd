# Left: a ping on the UART and a toggle of READY at pseudo-random instants; prints the
# pongs it gets back with the instant each line was complete.
import time
from machine import UART, Pin

uart = UART(1, baudrate=115200)
ready = Pin(4, Pin.OUT, value=0)
seed = 12345


def draw(n):
    global seed
    seed = (1103515245 * seed + 12345) & 0x7FFFFFFF
    return seed % n


buf = b""
sent = 0
while True:
    time.sleep_us(300 + draw(4000))
    if draw(3) == 0:
        sent += 1
        uart.write(b"ping %d\n" % sent)
        print("left sent ping", sent, "at", time.ticks_us())
    else:
        ready.value(1 - ready.value())
        print("left ready", ready.value(), "at", time.ticks_us())
    if uart.any():
        buf += uart.read()
        while b"\n" in buf:
            line, buf = buf.split(b"\n", 1)
            print("left got", line.decode(), "at", time.ticks_us())
