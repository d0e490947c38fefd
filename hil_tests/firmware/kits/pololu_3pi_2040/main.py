# A 3pi+ 2040's first mission, in the style of Pololu's demos (gyro_turn.py, encoder_test.py):
# button B (BOOTSEL) starts it; 25 cm straight by the encoders, then a quarter turn left by
# the gyro. The board support is the kitbot package (lib/kitbot: motors on PWM slice 7
# through mem32, PIO encoders, the LSM6DSO at 0x6B), which drives the 3pi+'s pins.
import math
import time

from kitbot.buttons import bootsel_pressed
from kitbot.encoders import Encoders
from kitbot.imu import IMU
from kitbot.motors import Motors

COUNTS_PER_REV = 12 * 29.86  # Standard Edition: 12 CPR through 29.86:1
WHEEL_MM = 32
MDPS_PER_LSB = 70  # +-2000 dps

motors = Motors()
encoders = Encoders()
imu = IMU()
imu.enable_default()


def travelled_mm():
    left, right = encoders.get_counts()
    return (left + right) / 2 / COUNTS_PER_REV * math.pi * WHEEL_MM


def settle(ms=300):
    end = time.ticks_add(time.ticks_ms(), ms)
    while time.ticks_diff(end, time.ticks_ms()) > 0:
        heading.update()
        time.sleep_ms(2)


class Heading:
    def __init__(self):
        self.deg = 0.0
        self.t = time.ticks_us()

    def update(self):
        now = time.ticks_us()
        rate = imu.gyro.read()[2] * MDPS_PER_LSB / 1000
        self.deg += rate * time.ticks_diff(now, self.t) / 1e6
        self.t = now
        return self.deg


heading = Heading()
while not bootsel_pressed():
    time.sleep_ms(10)
while bootsel_pressed():
    time.sleep_ms(10)
encoders.get_counts(reset=True)
while True:
    rest = 250 - travelled_mm()
    if rest <= 0.5:
        break
    speed = int(min(3000, 900 + 20 * rest))
    left, right = encoders.get_counts()
    skew = (left - right) * 50
    motors.set_speeds(speed - skew, speed + skew)
    time.sleep_ms(5)
motors.off()
settle()
print("straight_mm", travelled_mm())
heading.deg = 0.0
held = 0  # ms within half a degree of the target, wheels stopped
while held < 150:
    rest = 90 - heading.update()
    if abs(rest) <= 0.5:
        motors.off()
        held += 2
    else:
        held = 0
        speed = int(min(2000, 700 + 20 * abs(rest)))
        speed = speed if rest > 0 else -speed
        motors.set_speeds(-speed, speed)
    time.sleep_ms(2)
motors.off()
settle()
print("turned_deg", heading.deg)
print("done")
