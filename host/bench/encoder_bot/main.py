# A two-wheel Pico robot with Hall quadrature encoders (28 counts per motor turn behind a
# 98.5:1 gearbox) on a TB6612FNG: each wheel held at config.TARGET_CPS by a velocity PID
# run from a hardware Timer at 100 Hz; the encoders count every edge in Pin IRQs.
# After config.RUN_MS it brakes, waits for the wheels, and prints both counts.
import time

import config
from encoder import QuadEncoder
from machine import PWM, Pin, Timer

PWMA, AIN1, AIN2 = 16, 17, 18
PWMB, BIN1, BIN2 = 21, 20, 19
STBY = 22
ENC_LA, ENC_LB = 2, 3
ENC_RA, ENC_RB = 4, 5

PID_HZ = 100
KP, KI, KD = 0.00004, 0.0004, 0.0


class Motor:
    """One TB6612FNG channel: two direction pins and a PWM."""

    def __init__(self, pwm, in1, in2):
        self.pwm = PWM(Pin(pwm))
        self.pwm.freq(20000)
        self.in1 = Pin(in1, Pin.OUT)
        self.in2 = Pin(in2, Pin.OUT)

    def drive(self, duty):  # -1..1
        self.in1.value(1 if duty > 0 else 0)
        self.in2.value(1 if duty < 0 else 0)
        self.pwm.duty_u16(int(min(abs(duty), 1.0) * 65535))

    def brake(self):  # short brake: both inputs high
        self.in1.value(1)
        self.in2.value(1)
        self.pwm.duty_u16(65535)


class VelocityPID:
    """Counts per second from the count's change each period; a duty from the error."""

    def __init__(self, motor, encoder):
        self.motor = motor
        self.encoder = encoder
        self.target = 0
        self.last = encoder.count
        self.integral = 0.0
        self.error = 0.0

    def step(self):
        count = self.encoder.count
        cps = (count - self.last) * PID_HZ
        self.last = count
        error = self.target - cps
        self.integral = max(-1.0, min(1.0, self.integral + KI * error / PID_HZ))
        duty = KP * error + self.integral + KD * (error - self.error) * PID_HZ
        self.error = error
        self.motor.drive(max(-1.0, min(1.0, duty)))


stby = Pin(STBY, Pin.OUT, value=1)
left = VelocityPID(Motor(PWMA, AIN1, AIN2), QuadEncoder(ENC_LA, ENC_LB))
right = VelocityPID(Motor(PWMB, BIN1, BIN2), QuadEncoder(ENC_RA, ENC_RB))


def control(timer):
    left.step()
    right.step()


left.target = right.target = config.TARGET_CPS
tim = Timer(0)
tim.init(freq=PID_HZ, mode=Timer.PERIODIC, callback=control)
start = time.ticks_ms()
while time.ticks_diff(time.ticks_ms(), start) < config.RUN_MS:
    time.sleep_ms(500)
    print("cps", left.target, left.encoder.count, right.encoder.count)
tim.deinit()
left.motor.brake()
right.motor.brake()
time.sleep_ms(300)
print("counts", left.encoder.count, right.encoder.count)
