# A Timer callback that waits for a flag only the main program could set: it never ends on
# a board either (the main program never runs again).
import time
from machine import Timer

ready = False


def tick(_timer):
    while not ready:
        pass


Timer(-1).init(mode=Timer.ONE_SHOT, period=50, callback=tick)
while True:
    time.sleep_ms(10)
    ready = False
