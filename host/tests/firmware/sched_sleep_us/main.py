# Timers due inside a sleep_us(2500): the port runs scheduled callbacks only in the part of
# mp_hal_delay_us that handles events (rp2: its whole milliseconds; esp32: all but the
# last 155 us); the others run when it returns.
import time
from machine import Timer

t0 = time.ticks_us()
ran = []


def note(_t):
    ran.append(time.ticks_diff(time.ticks_us(), t0))


for due_us in (1500, 2200, 2400):
    Timer(-1, mode=Timer.ONE_SHOT, period=due_us, tick_hz=1_000_000, callback=note)
time.sleep_us(2500)
returned = time.ticks_diff(time.ticks_us(), t0)
time.sleep_ms(1)
print("R ran", ran)
print("R returned", returned)
