# WEDA B400 pool cleaner firmware (seeds 000/001): cleans a rectangular pool lane by
# lane, steering by stopping one track at a time, from a side sonar and two bumpers.
# The control step runs every 50 ms (the tracks' sample-and-hold quantum) on absolute
# deadlines; the sonar gives a distance every 500 ms, which mission.py turns into a
# filter update and a stop of whole quanta. A probe pin toggles at every step.
# The board file says how the sonar is wired: NMEA sentences on a UART (SONAR_UART)
# or one ADC input per side (SONAR_L_ADC, SONAR_R_ADC).
from machine import Pin
from micropython import const
from time import sleep_ms, ticks_add, ticks_diff, ticks_ms

import board
from mission import FRONT, REAR, Mission

QUANTUM_MS = const(50)


def sounders():
    if hasattr(board, "SONAR_UART"):
        from depth_sounder import DepthSounders

        return DepthSounders(board.SONAR_UART, board.SONAR_SELECT)
    from analog_depth_sounders import AnalogDepthSounders

    return AnalogDepthSounders(board.SONAR_L_ADC, board.SONAR_R_ADC)


def run():
    mission = Mission()
    stop_l = Pin(board.TRACK_L_STOP, Pin.OUT, value=mission.stop_left)  # held until the width is known
    stop_r = Pin(board.TRACK_R_STOP, Pin.OUT, value=mission.stop_right)
    front = Pin(board.BUMPER_FRONT, Pin.IN, Pin.PULL_UP)
    rear = Pin(board.BUMPER_REAR, Pin.IN, Pin.PULL_UP)
    probe = Pin(board.LOOP_PROBE, Pin.OUT, value=0)
    sonar = sounders()
    print("pool cleaner on", board.NAME, "control every", QUANTUM_MS, "ms")
    t0 = ticks_ms()
    deadline = t0
    while True:
        probe.toggle()
        depth = sonar.poll()
        # the bumpers are polled: the machine rests on a wall for a second as it reverses
        bumper = FRONT if not front.value() else (REAR if not rear.value() else 0)
        mission.quantum(ticks_diff(ticks_ms(), t0), depth, bumper)
        stop_l.value(mission.stop_left)
        stop_r.value(mission.stop_right)
        sonar.select(mission.sonar)
        deadline = ticks_add(deadline, QUANTUM_MS)
        sleep_ms(max(0, ticks_diff(deadline, ticks_ms())))


run()
