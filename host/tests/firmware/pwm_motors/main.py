# The same two motors as mem32_motors, driven through machine.PWM alone.
import time
from machine import PWM, Pin

right_dir = Pin(10, Pin.OUT, value=0)
left_dir = Pin(11, Pin.OUT, value=0)
right = PWM(Pin(14, Pin.OUT, value=0), freq=20833, duty_u16=0)
left = PWM(Pin(15, Pin.OUT, value=0), freq=20833, duty_u16=0)
left.duty_u16(32768)  # (CC 3000 of TOP 5999, as machine_pwm.c reads it back)
right.duty_u16(49151)  # (CC 4500)
print("R pwm", [left.duty_u16(), right.duty_u16(), left.freq(), right.freq()])
time.sleep_ms(1000)
left.duty_u16(0)
right.duty_u16(0)
