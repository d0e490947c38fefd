# A two-wheel Pico robot that holds its heading on its gyro and turns away from walls, as IMU
# code on a board is written: a hardware Timer at 208 Hz polls the LSM6DSOX's data-ready bits
# and reads gyro and accelerometer (12 bytes, readfrom_mem_into) whenever a new sample is
# there, integrating the turn rate; the main loop polls the VL53L0X for its result every 5 ms
# and steers the TB6612 at 50 Hz. After config.RUN_MS it stops and prints what it counted.
import time

import config
from lsm6dsox import LSM6DSOX
from machine import I2C, PWM, Pin, Timer
from vl53l0x import VL53L0X

PWMA, AIN1, AIN2 = 16, 17, 18
PWMB, BIN1, BIN2 = 21, 20, 19
STBY = 22
IMU_HZ = 208
CRUISE, TURN = 0.45, 0.35
WALL_MM = 400
KP = 0.02  # duty per degree of heading error


class Motor:
    def __init__(self, pwm, in1, in2):
        self.pwm = PWM(Pin(pwm), freq=20000, duty_u16=0)
        self.in1 = Pin(in1, Pin.OUT)
        self.in2 = Pin(in2, Pin.OUT)

    def drive(self, duty):  # -1..1
        self.in1.value(1 if duty > 0 else 0)
        self.in2.value(1 if duty < 0 else 0)
        self.pwm.duty_u16(int(min(abs(duty), 1.0) * 65535))


i2c = I2C(0, freq=400_000)
imu = LSM6DSOX(i2c)
tof = VL53L0X(i2c)
stby = Pin(STBY, Pin.OUT, value=1)
left, right = Motor(PWMA, AIN1, AIN2), Motor(PWMB, BIN1, BIN2)

heading = 0.0  # degrees, integrated from the gyro's z
samples = polls = 0
accel_sum = 0


def on_tick(timer):
    global heading, samples, polls, accel_sum
    polls += 1
    if imu.data_ready():
        gx, gy, gz, ax, ay, az = imu.read_raw()
        heading += gz * imu.gyro_scale / IMU_HZ
        accel_sum += az
        samples += 1


tim = Timer(0)
tim.init(freq=IMU_HZ, mode=Timer.PERIODIC, callback=on_tick)
target = 0.0
mm = 8190
ranges = 0
start = last_steer = time.ticks_ms()
while time.ticks_diff(time.ticks_ms(), start) < config.RUN_MS:
    time.sleep_ms(5)
    if tof.ready():
        mm = tof.read_mm()
        ranges += 1
        if mm < WALL_MM:
            target = heading + 90.0
    now = time.ticks_ms()
    if time.ticks_diff(now, last_steer) >= 20:
        last_steer = now
        error = target - heading
        base = TURN if abs(error) > 20 else CRUISE
        turn = max(-0.5, min(0.5, KP * error))
        left.drive(base - turn if abs(error) <= 20 else -turn)
        right.drive(base + turn if abs(error) <= 20 else turn)
tim.deinit()
left.drive(0)
right.drive(0)
print("imu_bot", samples, polls, ranges, int(heading), accel_sum // max(samples, 1))
