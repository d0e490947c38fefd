# Rover firmware: drives around a room, reads the front sonar every control step
# (the sonar itself gives a new range every 500 ms), slows down before walls, and
# when the bumper closes stops, backs off and turns. Control runs every 50 ms as an
# asyncio task on absolute deadlines; a probe pin toggles at each step so a logic
# analyser (or the harness) can check the period.
import asyncio
import math
from machine import Pin
from micropython import const
from time import ticks_add, ticks_diff, ticks_ms

import board
from analog_sonar import AnalogSonar
from bumper import Bumper
from encoder import QuadratureEncoder
from motor import HBridgeMotor
from rover_control import STATE_NAMES, Rover, WheelSpeedPI

CONTROL_PERIOD_MS = const(50)
WHEEL_RADIUS_M = 0.033
COUNTS_PER_REV = const(40)  # 20-cycle quadrature disc, both edges of channel A
M_PER_COUNT = 2 * math.pi * WHEEL_RADIUS_M / COUNTS_PER_REV


async def control(rover, left, right, enc_l, enc_r, sonar, bumper, probe):
    period_s = CONTROL_PERIOD_MS / 1000
    pi_l = WheelSpeedPI(M_PER_COUNT, period_s)
    pi_r = WheelSpeedPI(M_PER_COUNT, period_s)
    state = rover.state
    deadline = ticks_ms()
    while True:
        probe.toggle()
        range_m = sonar.read_m()
        bumped = bumper.latched
        bumper.clear()
        v_l, v_r = rover.step(range_m, bumped)
        if rover.state != state:
            state = rover.state
            pi_l.reset()
            pi_r.reset()
            print("rover:", STATE_NAMES[state], "range %.2f m" % range_m)
        left.drive(pi_l.update(v_l, enc_l.take()))
        right.drive(pi_r.update(v_r, enc_r.take()))
        deadline = ticks_add(deadline, CONTROL_PERIOD_MS)
        await asyncio.sleep_ms(max(0, ticks_diff(deadline, ticks_ms())))


def main():
    left = HBridgeMotor(board.MOTOR_L_IN1, board.MOTOR_L_IN2, board.MOTOR_L_PWM)
    right = HBridgeMotor(board.MOTOR_R_IN1, board.MOTOR_R_IN2, board.MOTOR_R_PWM)
    enc_l = QuadratureEncoder(board.ENC_L_A, board.ENC_L_B)
    enc_r = QuadratureEncoder(board.ENC_R_A, board.ENC_R_B)
    sonar = AnalogSonar(board.SONAR_ADC)
    bumper = Bumper(board.BUMPER)
    probe = Pin(board.LOOP_PROBE, Pin.OUT, value=0)
    print("rover on", board.NAME, "control every", CONTROL_PERIOD_MS, "ms")
    asyncio.run(control(Rover(), left, right, enc_l, enc_r, sonar, bumper, probe))


main()
