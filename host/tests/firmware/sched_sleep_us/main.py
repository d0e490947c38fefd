# Timers due inside a sleep_us(2500), then a sleep_ms(3): the port runs scheduled callbacks
# only in the part of mp_hal_delay_us that handles events (rp2: its whole milliseconds;
# esp32: all but the last 155 us), and in mp_hal_delay_ms (rp2: all of it; esp32: all but
# the last 155 us, its mp_hal_delay_us); the others run when it returns.
import sys
import time
from machine import Timer

# the rp2 port has soft timers only (Timer(-1)); the ESP32's are its hardware timers 0..3
IDS = (-1, -1, -1) if sys.platform == "rp2" else (0, 1, 2)

t0 = time.ticks_us()
ran = []


def note(_t):
    ran.append(time.ticks_diff(time.ticks_us(), t0))


for tid, due_us in zip(IDS, (1500, 2200, 2400)):
    Timer(tid, mode=Timer.ONE_SHOT, period=due_us, tick_hz=1_000_000, callback=note)
time.sleep_us(2500)
returned = time.ticks_diff(time.ticks_us(), t0)
while len(ran) < 3:  # those still queued run one at a pending check (here each clock read)
    time.ticks_us()
in_us = ran[:]
t0 = time.ticks_us()
del ran[:]
for tid, due_us in zip(IDS, (1500, 2900)):
    Timer(tid, mode=Timer.ONE_SHOT, period=due_us, tick_hz=1_000_000, callback=note)
time.sleep_ms(3)
returned_ms = time.ticks_diff(time.ticks_us(), t0)
time.sleep_ms(1)
print("R ran", in_us)
print("R returned", returned)
print("R ran_ms", ran)
print("R returned_ms", returned_ms)
