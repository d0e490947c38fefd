# A motor driver asking for more than full duty, as XRPLib's does when its PID saturates
# (int(abs(effort) * 65535) with an effort of 1.04), and for a negative one.
from machine import PWM, Pin

pwm = PWM(Pin(15), freq=20833)
try:
    pwm.duty_u16(68343)
    print("R over", pwm.duty_u16())
except ValueError as e:
    print("R over", repr(str(e)))
try:
    pwm.duty_u16(-1)
    print("R negative", pwm.duty_u16())
except ValueError as e:
    print("R negative", repr(str(e)))
