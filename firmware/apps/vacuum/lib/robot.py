# RoboClean, the vacuum cleaner robot of seed 003, on a MicroPython board: the Arduino
# Mega's tasks (§4.1) on a 50 ms quantum: the pose (odometry, then go-to-goal or
# avoidance) every 100 ms, sensing (one ping at the servo's settled angle, then one servo
# step) every 150 ms, the behaviour switch every 500 ms; encoder slots counted in IRQs.
# The ping is the only blocking work (at most 25.2 ms): it runs last in its quantum, so
# no task starts late. Each task toggles a probe pin; the ping probe is high while it lasts.
import math
from machine import Pin
from micropython import const
from time import sleep_ms, sleep_us, ticks_add, ticks_diff, ticks_ms, ticks_us

import board
import mission_config
from avoidance import SWEEP_DEG
from chassis import PWM_FULL, SLOTS, TRACK_CM, WHEEL_DIAMETER_CM
from go_to_goal import HeadingController
from hcsr04 import HCSR04
from motor import HBridgeMotor
from navigator import MODE_NAMES, Navigator
from odometry import Odometry
from scheduler import QuantumScheduler
from sg90 import SG90
from slot_encoder import SlotEncoder, read_counts

QUANTUM_MS = const(50)
QUANTUM_US = const(50_000)
POSE = const(0)
BEHAVIOUR = const(1)
SENSE = const(2)
TASKS = ((POSE, 2), (BEHAVIOUR, 10), (SENSE, 3))  # 100, 500 and 150 ms; the ping last
MOTOR_FREQ_HZ = const(1000)


class SensorHead:
    """The servo sweeps 10, 45, 90, 135, 170, 135, ... deg (no fly-back); each sensing
    task pings at the angle the servo has reached, then commands the next one."""

    def __init__(self, servo, sonar, probe):
        self.servo = servo
        self.sonar = sonar
        self.probe = probe
        self.index = 0
        self._step = 1
        servo.move(SWEEP_DEG[0])

    def sense(self):
        """(sweep index, range in cm or None), or None while the servo still turns."""
        if not self.servo.settled():
            return None
        i = self.index
        self.probe.value(1)
        d_cm = self.sonar.distance_cm()
        self.probe.value(0)
        if not 0 <= i + self._step < len(SWEEP_DEG):
            self._step = -self._step
        self.index = i + self._step
        self.servo.move(SWEEP_DEG[self.index])
        return i, d_cm


class Wheels:
    """moveMotor(LEFT/RIGHT, FORWARD, pwm) with an 8-bit PWM, as the listing drives them."""

    def __init__(self):
        self.left = HBridgeMotor(board.MOTOR_L_IN1, board.MOTOR_L_IN2, board.MOTOR_L_PWM, freq_hz=MOTOR_FREQ_HZ)
        self.right = HBridgeMotor(board.MOTOR_R_IN1, board.MOTOR_R_IN2, board.MOTOR_R_PWM, freq_hz=MOTOR_FREQ_HZ)

    def move(self, pwm_l, pwm_r):
        self.left.drive(pwm_l / PWM_FULL)
        self.right.drive(pwm_r / PWM_FULL)


def make_navigator(m):
    bugs = m["bugs"]
    kp, ki, kd = m["gains"]
    controller = HeadingController(
        kp,
        ki,
        kd,
        delta_ms=QUANTUM_MS * TASKS[0][1],
        no_wrap="heading_no_wrap" in bugs,
        derivative_in_ms="derivative_in_ms" in bugs,
    )
    return Navigator(m["goals"], controller)


def make_odometry(m):
    x, y, phi_deg = m["start"]
    mean_bug = "mean_filter_no_reset" in m["bugs"]
    return Odometry(
        x,
        y,
        math.radians(phi_deg),
        wheel_diameter_cm=WHEEL_DIAMETER_CM,
        slots=SLOTS,
        track_cm=TRACK_CM,
        mean_bug=mean_bug,
    )


def run():
    m = mission_config.load()
    wheels = Wheels()
    enc_l, enc_r = SlotEncoder(board.ENC_L), SlotEncoder(board.ENC_R)
    probes = [Pin(p, Pin.OUT, value=0) for p in (board.POSE_PROBE, board.BEHAVIOUR_PROBE, board.SENSE_PROBE)]
    quantum_probe = Pin(board.QUANTUM_PROBE, Pin.OUT, value=0)
    head = SensorHead(SG90(board.SERVO_PWM), HCSR04(board.SONAR_TRIG, board.SONAR_ECHO), Pin(board.PING_PROBE, Pin.OUT))
    odometry = make_odometry(m)
    nav = make_navigator(m)
    scheduler = QuantumScheduler(TASKS)
    print("RoboClean on", board.NAME, "goals", m["goals"], "gains", m["gains"], "bugs", m["bugs"])
    print("pose columns: t_ms x_cm y_cm phi_deg")
    pose = (odometry.x, odometry.y, odometry.phi)
    t0 = ticks_ms()
    deadline = ticks_us()
    while True:
        quantum_probe.toggle()
        for task in scheduler.due():
            probes[task].toggle()
            if task == POSE:
                pose = odometry.update(*read_counts(enc_l, enc_r))
                reached = len(nav.reached)
                wheels.move(*nav.control(pose))
                if len(nav.reached) > reached:
                    report(t0, "goal %d of %d reached" % (len(nav.reached), len(nav.goals)), pose)
            elif task == BEHAVIOUR:
                if nav.check(pose):
                    report(t0, "behaviour: " + MODE_NAMES[nav.mode], pose)
                log_pose(t0, pose)
            else:
                reading = head.sense()
                if reading is not None:
                    nav.obstacles.add(reading[0], reading[1], pose)
        deadline = ticks_add(deadline, QUANTUM_US)  # absolute deadlines: no drift
        wait_us(deadline)


def wait_us(deadline):
    left_us = ticks_diff(deadline, ticks_us())
    if left_us > 0:
        sleep_ms(left_us // 1000)  # the board idles (or serves Wi-Fi) meanwhile
        sleep_us(left_us % 1000)


def log_pose(t0, pose):
    """The odometry's pose for the console, every behaviour task (500 ms)."""
    print("pose %d %.1f %.1f %.2f" % (ticks_diff(ticks_ms(), t0), pose[0], pose[1], math.degrees(pose[2])))


def report(t0, what, pose):
    print(
        "%.2f s: %s, odometry (%.1f, %.1f) cm %.1f deg"
        % (ticks_diff(ticks_ms(), t0) / 1000, what, pose[0], pose[1], math.degrees(pose[2]))
    )
