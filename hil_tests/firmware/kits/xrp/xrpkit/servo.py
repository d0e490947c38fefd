# A hobby servo on a 50 Hz PWM: 0..180 degrees as 500..2500 us.
from machine import PWM, Pin


class Servo:
    def __init__(self, pin):
        self.pwm = PWM(Pin(pin, Pin.OUT), freq=50, duty_u16=0)

    def set_angle(self, degrees):
        degrees = max(0, min(180, degrees))
        self.pwm.duty_ns(int((500 + degrees / 180 * 2000) * 1000))

    def free(self):
        self.pwm.duty_u16(0)
