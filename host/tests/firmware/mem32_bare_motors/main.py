# The two motors of mem32_motors with no machine.PWM at all: slice 7 set up through its
# registers, GP14 and GP15 given to the PWM function through IO_BANK0's FUNCSEL.
import time
from machine import Pin, mem32

PWM_BASE = 0x40050000
CH7 = PWM_BASE + 7 * 0x14
CH7_CSR, CH7_DIV, CH7_CC, CH7_TOP = CH7, CH7 + 0x04, CH7 + 0x0C, CH7 + 0x10
IO_BANK0 = 0x40014000
FUNC_PWM = 4

right_dir = Pin(10, Pin.OUT, value=0)
left_dir = Pin(11, Pin.OUT, value=0)
mem32[CH7_TOP] = 5999
mem32[CH7_DIV] = 16
mem32[CH7_CC] = (3000 << 16) | 4500
mem32[CH7_CSR] = 1  # EN
for gpio in (14, 15):
    mem32[IO_BANK0 + 8 * gpio + 4] = FUNC_PWM
time.sleep_ms(1000)
mem32[CH7_CC] = 0
