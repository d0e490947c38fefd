# DC motor behind one channel of a TB6612FNG / L298N-style H-bridge: two direction
# pins and a PWM enable.
from machine import PWM, Pin

PWM_FREQ_HZ = 20_000  # above hearing, within the TB6612FNG's 100 kHz (an L298N wants 1 kHz or so)


class HBridgeMotor:
    def __init__(self, in1, in2, pwm, invert=False, freq_hz=PWM_FREQ_HZ):
        self._in1 = Pin(in1, Pin.OUT, value=0)
        self._in2 = Pin(in2, Pin.OUT, value=0)
        self._pwm = PWM(Pin(pwm, Pin.OUT), freq=freq_hz, duty_u16=0)
        self._sign = -1 if invert else 1
        self.command = 0.0

    def drive(self, command):
        """command in -1.0 .. 1.0: sign is direction, magnitude is duty."""
        command = max(-1.0, min(1.0, command))
        self.command = command
        forward = command * self._sign >= 0
        self._in1.value(1 if forward and command else 0)
        self._in2.value(1 if not forward and command else 0)
        self._pwm.duty_u16(int(abs(command) * 65535))

    def brake(self):
        self.command = 0.0
        self._pwm.duty_u16(0)
        self._in1.value(0)
        self._in2.value(0)
