import machine
from time import sleep_ms

print("R cause", machine.reset_cause())
sleep_ms(100)
machine.reset()
