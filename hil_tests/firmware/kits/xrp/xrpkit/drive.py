# The drivetrain: straight by the encoders, turns by the gyro, forwards until the
# rangefinder sees something near. Distances in cm, angles in degrees (left positive).
import math
import time

WHEEL_DIAMETER_CM = 6.0
TRACK_CM = 15.5


class Drivetrain:
    def __init__(self, left_motor, right_motor, left_encoder, right_encoder, imu=None):
        self.motors = (left_motor, right_motor)
        self.encoders = (left_encoder, right_encoder)
        self.imu = imu

    def set_effort(self, left, right):
        self.motors[0].set_effort(left)
        self.motors[1].set_effort(right)

    def stop(self, settle_ms=300):
        self.set_effort(0, 0)
        end = time.ticks_add(time.ticks_ms(), settle_ms)
        while time.ticks_diff(end, time.ticks_ms()) > 0:  # (the gyro still counts the coast)
            if self.imu:
                self.imu.update()
            time.sleep_ms(5)

    def distance_cm(self):
        left, right = (e.revolutions() for e in self.encoders)
        return (left + right) / 2 * math.pi * WHEEL_DIAMETER_CM

    def straight(self, cm, max_effort=0.5):
        for e in self.encoders:
            e.reset()
        while True:
            left, right = (e.revolutions() for e in self.encoders)
            rest = cm - (left + right) / 2 * math.pi * WHEEL_DIAMETER_CM
            if rest <= 0.05:
                break
            effort = min(max_effort, 0.1 + 0.06 * rest)
            skew = (left - right) * 2.0  # hold the wheels together
            self.set_effort(effort - skew, effort + skew)
            time.sleep_ms(5)
        self.stop()
        return self.distance_cm()

    def turn(self, degrees, max_effort=0.5):
        self.imu.reset_heading()
        while True:
            rest = degrees - self.imu.update()
            if abs(rest) <= 0.3:
                break
            effort = min(max_effort, 0.08 + 0.01 * abs(rest))
            effort = effort if rest > 0 else -effort
            self.set_effort(-effort, effort)
            time.sleep_ms(5)
        self.stop()
        return self.imu.heading

    def until_near(self, ranger, cm, effort=0.4):
        while True:
            seen = ranger.distance_cm()
            if seen <= cm:
                break
            self.set_effort(effort, effort)
            time.sleep_ms(20)
        self.stop()
        return ranger.distance_cm()
