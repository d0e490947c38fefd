# The drive motors. The RP2040 beta controller's driver takes a direction pin and a speed
# PWM; the RP2350 controller's, a PWM per direction. Effort runs from -1 to 1.
from machine import PWM, Pin

_FULL = 65535


class DirSpeedMotor:
    def __init__(self, dir_pin, speed_pin, flip=False):
        self.dir = Pin(dir_pin, Pin.OUT, value=0)
        self.speed = PWM(Pin(speed_pin, Pin.OUT), freq=50, duty_u16=0)
        self.flip = flip

    def set_effort(self, effort):
        effort = max(-1.0, min(1.0, effort))
        self.dir.value(1 if (effort < 0) != self.flip else 0)
        self.speed.duty_u16(int(abs(effort) * _FULL))


class TwoPwmMotor:
    def __init__(self, in1_pin, in2_pin, flip=False):
        self.fwd = PWM(Pin(in1_pin, Pin.OUT), freq=50, duty_u16=0)
        self.back = PWM(Pin(in2_pin, Pin.OUT), freq=50, duty_u16=0)
        self.flip = flip

    def set_effort(self, effort):
        # as the vendor's DualPWMMotor: a positive effort drives IN2, unless flipped
        effort = max(-1.0, min(1.0, effort))
        in1 = (effort < 0) != self.flip
        duty = int(abs(effort) * _FULL)
        self.fwd.duty_u16(duty if in1 else 0)
        self.back.duty_u16(0 if in1 else duty)
