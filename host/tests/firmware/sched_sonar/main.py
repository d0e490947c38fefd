# A 10 ms control loop on a Timer (it toggles the loop probe) and a main program that reads
# an ultrasonic ranger with time_pulse_us: on a board the read is a C busy loop, so the
# ticks that come due meanwhile wait for it to return and the control loop runs late.
import time
from machine import Pin, Timer, time_pulse_us

probe = Pin(15, Pin.OUT, value=0)
echo = Pin(36, Pin.IN)
inside = False
seen_inside = 0
ticks = []
t0 = time.ticks_us()


def control(_t):
    global seen_inside
    if inside:
        seen_inside += 1
    probe.toggle()
    ticks.append(time.ticks_diff(time.ticks_us(), t0))


Timer(0, mode=Timer.PERIODIC, period=10, callback=control)
reads = []
for _ in range(4):
    inside = True
    width = time_pulse_us(echo, 1, 40_000)
    inside = False
    reads.append((width, time.ticks_diff(time.ticks_us(), t0)))
    time.sleep_ms(25)
print("R inside", seen_inside)
print("R ticks", ticks)
print("R reads", reads)
