# The navigator of a two-board rover, on an ESP32: an HC-SR04 ahead, the motor board on
# UART2. Every 100 ms it ranges and sends the wheel speeds ("V <left> <right>\n", encoder
# counts a second): ahead, or a turn on the spot away from anything closer than 30 cm.
# It prints the odometry the motor board answers with. After RUN_S it stops commanding.
import time

from machine import UART, Pin, time_pulse_us

TRIG, ECHO = 5, 18
LINK_UART = 2  # TX GPIO17, RX GPIO16

CRUISE = 500  # encoder counts a second
TURN = 300
STOP_CM = 30
TURN_MS = 700
LOOP_MS = 100
RUN_S = 5


def distance_cm(trig, echo):
    trig.value(1)
    time.sleep_us(10)
    trig.value(0)
    t = time_pulse_us(echo, 1, 30000)
    return None if t < 0 else t / 58.0


trig = Pin(TRIG, Pin.OUT, value=0)
echo = Pin(ECHO, Pin.IN)
link = UART(LINK_UART, baudrate=115200)
print("nav: go")
start = time.ticks_ms()
turning_until = None
buf = b""
while time.ticks_diff(time.ticks_ms(), start) < RUN_S * 1000:
    t0 = time.ticks_ms()
    d = distance_cm(trig, echo)
    if turning_until is not None and time.ticks_diff(t0, turning_until) >= 0:
        turning_until = None
    if turning_until is None and d is not None and d < STOP_CM:
        print("nav: obstacle at %d cm, turning" % d)
        turning_until = time.ticks_add(t0, TURN_MS)
    speeds = (CRUISE, CRUISE) if turning_until is None else (-TURN, TURN)
    link.write(b"V %d %d\n" % speeds)
    if link.any():
        buf += link.read()
        while b"\n" in buf:
            line, buf = buf.split(b"\n", 1)
            print("nav: odometry", line.decode()[2:])
    time.sleep_ms(max(0, LOOP_MS - time.ticks_diff(time.ticks_ms(), t0)))
print("nav: done")
while True:
    time.sleep_ms(1000)
