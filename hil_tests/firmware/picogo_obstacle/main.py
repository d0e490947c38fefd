# Forward until either IR obstacle sensor sees the wall, then stop (the Pico-Go demos' way:
# the motors by their TB6612 pins, the sensors read low while something is near; written
# here, not copied).
import time
from machine import PWM, Pin

pwma, pwmb = PWM(Pin(16)), PWM(Pin(21))
pwma.freq(1000)
pwmb.freq(1000)
ain2, ain1, bin1, bin2 = Pin(17, Pin.OUT), Pin(18, Pin.OUT), Pin(19, Pin.OUT), Pin(20, Pin.OUT)
dsr, dsl = Pin(2, Pin.IN), Pin(3, Pin.IN)


def drive(speed):
    pwma.duty_u16(int(speed * 0xFFFF / 100))
    pwmb.duty_u16(int(speed * 0xFFFF / 100))
    ain1.value(0)
    ain2.value(1 if speed else 0)
    bin1.value(0)
    bin2.value(1 if speed else 0)


print("start", dsl.value(), dsr.value())
drive(30)
while dsl.value() == 1 and dsr.value() == 1:
    time.sleep_ms(2)
drive(0)
print("blocked", dsl.value(), dsr.value(), time.ticks_ms())
time.sleep_ms(300)
print("done")
