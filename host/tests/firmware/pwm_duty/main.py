# ESP32-style PWM: the 10-bit duty() of the esp32 port, and duty= when it is made.
import sys
from machine import PWM, Pin

pwm = PWM(Pin(25), freq=1000, duty=512)
print("R made", [pwm.duty_u16(), pwm.duty()])
pwm.duty(1023)
print("R full", [pwm.duty_u16(), pwm.duty()])
pwm.duty(0)
print("R off", pwm.duty_u16())
print("R version", list(sys.implementation.version[:2]))
