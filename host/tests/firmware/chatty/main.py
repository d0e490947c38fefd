# A firmware that prints a kilobyte every millisecond (a debug build left chatty).
import time

line = "x" * 1023
n = 0
while True:
    print(line)
    n += 1
    time.sleep_ms(1)
