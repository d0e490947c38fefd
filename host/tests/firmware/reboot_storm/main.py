# A sensor that never answers: the firmware gives it RETRY_MS (config.py, beside it) and
# then resets the board to try again, as many do, forever.
import machine
import time

from config import RETRY_MS

ready = machine.Pin(23, machine.Pin.IN)
print("boot", machine.reset_cause())
time.sleep_ms(RETRY_MS)
if not ready.value():
    machine.reset()
