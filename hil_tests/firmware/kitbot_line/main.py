# kitbot following a line in the style of Pololu's 3pi+ line follower demo: BOOTSEL starts
# it; the QTR channels' discharge times (each timed by machine.time_pulse_us), scaled
# between the floor's white and the line's black as the start saw them (0 white .. 1000
# black), give the line's position under the array (0 .. 2000, 1000 centred), and a PD
# correction on it steers the wheels every 10 ms.
import time
from micropython import const

from kitbot import LineSensors, Motors, bootsel_pressed

BASE_SPEED = const(3600)  # of MAX_SPEED 6000
KP = 4.0  # speed per unit of position error
KD = 20.0  # speed per unit of position change a read
PERIOD_MS = const(10)

line = LineSensors()
motors = Motors()
while not bootsel_pressed():
    time.sleep_ms(10)
while bootsel_pressed():
    time.sleep_ms(10)
first = list(line.read())
white, black = min(first), max(first)  # (the middle channel starts on the line, the others beside it)
print("calibrated", white, black)


def position(data):
    total = weighted = 0
    for i in range(len(data)):
        v = min(1000, max(0, (data[i] - white) * 1000 // (black - white)))
        total += v
        weighted += v * 1000 * i
    return weighted // total if total > 100 else -1


last = 1000
lost = False
while True:
    at = position([line.read_one(i) for i in range(3)])
    if (at < 0) != lost:
        lost = not lost
        print("lost" if lost else "found", time.ticks_ms())
    if at < 0:
        at = 0 if last < 1000 else 2000  # off the line: it was last seen to that side
    error = at - 1000  # > 0: the line is to the right (channel 2 is on the right)
    turn = int(KP * error + KD * (at - last))
    last = at
    motors.set_speeds(BASE_SPEED + turn, BASE_SPEED - turn)
    time.sleep_ms(PERIOD_MS)
