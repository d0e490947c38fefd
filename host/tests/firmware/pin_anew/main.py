# A driver that makes its pins anew at each read (as Kitronik's getDistance does): a pin
# made as it already is changes nothing for the host; another pull, another level, or a
# pin a PWM took since, does. A PWM's frequency set again as it is tells the host nothing.
import time
from machine import PWM, Pin

echo = Pin(36, Pin.IN)
out = Pin(26, Pin.OUT, value=0)
for _ in range(5):
    echo = Pin(36, Pin.IN)
    out = Pin(26, Pin.OUT)
    time.sleep_ms(1)
print("R anew", (echo.value(), out.value()))
Pin(36, Pin.IN, Pin.PULL_UP)  # another pull
Pin(26, Pin.OUT, value=1)  # another level
Pin(26, Pin.OUT, value=1)  # (as it is again)
taken = Pin(25, Pin.OUT, value=0)
pwm = PWM(taken, freq=1000, duty_u16=0)
for _ in range(3):
    pwm.freq(1000)  # the same frequency: nothing for the host
pwm.freq(2000)
Pin(25, Pin.OUT, value=0)  # the PWM took it: the pin's again
time.sleep_ms(1)
print("R after", (echo.value(), out.value()))
