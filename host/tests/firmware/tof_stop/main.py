# A VL53L0X read the way its drivers read it (back-to-back ranging: SYSRANGE_START 0x02,
# wait for RESULT_INTERRUPT_STATUS, the range at RESULT_RANGE_STATUS + 10, clear the
# interrupt): the robot drives at a wall on a TB6612 and stops when the range is 0.3 m.
import time
from machine import I2C, PWM, Pin

i2c = I2C(0, scl=Pin(22), sda=Pin(21))
ADDR = 0x29
print("R ident", list(i2c.readfrom_mem(ADDR, 0xC0, 3)))

ain1, ain2, bin1, bin2 = Pin(17, Pin.OUT), Pin(18, Pin.OUT), Pin(22 + 1, Pin.OUT), Pin(19, Pin.OUT)
pwm_a, pwm_b = PWM(Pin(16), freq=20_000, duty_u16=0), PWM(Pin(4), freq=20_000, duty_u16=0)


def drive(duty_u16):
    ain1.value(1)
    ain2.value(0)
    bin1.value(1)
    bin2.value(0)
    pwm_a.duty_u16(duty_u16)
    pwm_b.duty_u16(duty_u16)


def range_mm():
    while not i2c.readfrom_mem(ADDR, 0x13, 1)[0] & 0x07:
        time.sleep_ms(1)
    mm = int.from_bytes(i2c.readfrom_mem(ADDR, 0x14 + 10, 2), "big")
    i2c.writeto_mem(ADDR, 0x0B, b"\x01")
    return mm


i2c.writeto_mem(ADDR, 0x00, b"\x02")  # back-to-back
first = range_mm()
t0 = time.ticks_ms()
n = 1
drive(40_000)
mm = first
while mm > 300:
    mm = range_mm()
    n += 1
drive(0)
print("R first_mm", first)
print("R stop_mm", mm)
print("R period_ms", time.ticks_diff(time.ticks_ms(), t0) / (n - 1))
