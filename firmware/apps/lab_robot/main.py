# Dead-reckoning lab robot firmware (seed 004, "Mobile Robots Lab Report"): the seed's
# Aria programs on a small two-wheel robot. A jumper picks the program at reset, as the
# seed's makefile picked RUNASNx: open, the square path (SquareBot, asn1); fitted, left-
# wall following through the S-curve canyon (SCurveBot, asn4) with SonarBot's sonar
# polling. Every 50 ms on absolute deadlines: take the encoder counts (decoded in IRQ
# handlers), update the odometry, run the program, drive the wheel speed loops. A probe
# pin toggles at every step. docs/lab_robot.md has the algorithms and their seed.
import math
import micropython
from machine import Pin
from micropython import const
from time import sleep_us, ticks_add, ticks_diff, ticks_us

import board
from dead_reckoning import MM_PER_COUNT, TRACK_MM, Odometry
from drivers import Drv8833Motor, QuadratureEncoder, SonarChain
from goto import GoTo
from square import Square
from wall_follow import WallFollow
from wheel_speed import WheelSpeed

if hasattr(micropython, "alloc_emergency_exception_buf"):  # not on every port (unix)
    micropython.alloc_emergency_exception_buf(100)  # a traceback from a hard IRQ handler

CONTROL_MS = const(50)
CONTROL_US = const(50_000)  # deadlines in us: the sonar's RX pulse must not shift the steps
SONAR_START_MS = const(1000)  # SonarBot: ArUtil::sleep(1000) before the first read
SONAR_MS = const(100)  # then ArUtil::sleep(100) between reads
RANGING_MS = const(50)  # an LV-EZ reading is ready 49 ms after RX: command it a step early
POSE_LOG_MS = const(250)  # a pose line on the console this often, to plot against a track


class Robot:
    """The wheels as the programs see them: odometry in, (v, w) out."""

    def __init__(self):
        self.motor_l = Drv8833Motor(board.MOTOR_L_IN1, board.MOTOR_L_IN2)
        self.motor_r = Drv8833Motor(board.MOTOR_R_IN1, board.MOTOR_R_IN2)
        self.enc_l = QuadratureEncoder(board.ENC_L_A, board.ENC_L_B)
        self.enc_r = QuadratureEncoder(board.ENC_R_A, board.ENC_R_B)
        self.speed_l = WheelSpeed()
        self.speed_r = WheelSpeed()
        self.odo = Odometry()
        self._ds_l = self._ds_r = 0.0

    def sense(self, dt_ms):
        self._ds_l = self.enc_l.take() * MM_PER_COUNT
        self._ds_r = self.enc_r.take() * MM_PER_COUNT
        self.odo.update(self._ds_l, self._ds_r, dt_ms)

    def drive(self, v_mm_s, w_rad_s, dt_ms):
        half = w_rad_s * TRACK_MM / 2
        self.motor_l.drive(self.speed_l.update(v_mm_s - half, self._ds_l, dt_ms))
        self.motor_r.drive(self.speed_r.update(v_mm_s + half, self._ds_r, dt_ms))

    def log_pose(self, t_ms):
        """The dead-reckoned pose for the console: pose t_ms x_mm y_mm theta_rad."""
        odo = self.odo
        print("pose %d %.1f %.1f %.4f" % (t_ms, odo.x_mm, odo.y_mm, odo.theta_rad))

    def report(self, t_ms, what):
        odo, dl, dr = self.odo, self.enc_l.decoder, self.enc_r.decoder
        print(
            "%s at %d ms: x %.1f mm y %.1f mm theta %.2f deg; S_L %.1f mm S_R %.1f mm"
            % (what, t_ms, odo.x_mm, odo.y_mm, math.degrees(odo.theta_rad), odo.s_l_mm, odo.s_r_mm)
        )
        print(
            "encoders: left %d counts %d errors %d idle, right %d counts %d errors %d idle"
            % (dl.count, dl.errors, dl.idle, dr.count, dr.errors, dr.idle)
        )


class SquarePath:
    """SquareBot: the 2 m square by go-to goals."""

    name = "square path"

    def __init__(self, robot):
        self.square = Square(GoTo())
        self.robot = robot
        self.command = (0.0, 0.0)

    def step(self, t_ms):
        if not self.square.done:
            self.command = self.square.step(self.robot.odo, t_ms)
            if self.square.done:
                self.robot.report(t_ms, "square done")
        return self.command


class CanyonRun:
    """SCurveBot: left-wall following at 400 mm/s from the sonar chain, read as SonarBot
    reads: at 1000 ms, then every 100 ms, each ranging commanded a step before its read."""

    name = "left-wall following"

    def __init__(self, robot):
        self.robot = robot
        self.sonars = SonarChain(board.SONAR_RX, (board.SONAR_F_ADC, board.SONAR_L_ADC, board.SONAR_LF_ADC))
        self.follow = WallFollow()
        self.command = (0.0, 0.0)
        self._read_ms = SONAR_START_MS

    def step(self, t_ms):
        if self.follow.done:
            return self.command
        if t_ms == self._read_ms:
            front, left, left_front = self.sonars.read_mm()
            v, w_deg_s = self.follow.step(front, left, left_front)
            self.command = (v, math.radians(w_deg_s))
            self._read_ms += SONAR_MS
            if self.follow.done:
                self.robot.report(t_ms, "nowall: canyon end")
                return self.command
        if t_ms == self._read_ms - RANGING_MS:
            self.sonars.trigger()
        return self.command


def run():
    robot = Robot()
    fitted = Pin(board.PROGRAM_JUMPER, Pin.IN, Pin.PULL_UP).value() == 0
    program = CanyonRun(robot) if fitted else SquarePath(robot)
    probe = Pin(board.LOOP_PROBE, Pin.OUT, value=0)
    print("lab robot on", board.NAME + ":", program.name, "control every", CONTROL_MS, "ms")
    print("pose columns: t_ms x_mm y_mm theta_rad")
    t_ms = 0  # program time, counted in steps (ticks_us wraps after 18 minutes)
    last = deadline = ticks_us()
    while True:
        probe.toggle()
        now = ticks_us()
        dt_ms = ticks_diff(now, last) / 1000
        last = now
        robot.sense(dt_ms)
        if t_ms % POSE_LOG_MS == 0:
            robot.log_pose(t_ms)
        v, w = program.step(t_ms)
        robot.drive(v, w, dt_ms)
        t_ms += CONTROL_MS
        deadline = ticks_add(deadline, CONTROL_US)
        sleep_us(max(0, ticks_diff(deadline, ticks_us())))


run()
