# The 3pi+ 2040's yellow LED dimmed by a PWM on GP25 (the library's splash loader fades it:
# PWM(YellowLED().pin)), then driven as an output again, beside button A on the same pin.
import time
from machine import PWM, Pin

pin = Pin(25, Pin.OUT)
pin.high()  # off (lit while low)
pwm = PWM(pin)
pwm.freq(1000)
for step, duty in enumerate((60000, 5000)):  # mostly high: off; mostly low: lit
    pwm.duty_u16(duty)
    time.sleep_ms(10)
    print("R pwm", step, duty)
    time.sleep_ms(10)
pwm.deinit()
pin = Pin(25, Pin.OUT)
pin.high()
time.sleep_ms(10)
print("R pin", 1)
time.sleep_ms(10)
print("done")
