# Two motors on one PWM slice through its registers, as a kit's motor driver does: the
# PWM made at 20833 Hz, then slice 7's TOP, DIV and CC written through machine.mem32
# (RP2040 datasheet 4.5.3: slices 0x14 apart from 0x40050000; CC holds A low, B high).
import time
from machine import PWM, Pin, mem16, mem32

PWM_BASE = 0x40050000
CH7 = PWM_BASE + 7 * 0x14
CH7_CSR, CH7_DIV, CH7_CC, CH7_TOP = CH7, CH7 + 0x04, CH7 + 0x0C, CH7 + 0x10
SPEEDS = 6000

right_dir = Pin(10, Pin.OUT, value=0)
left_dir = Pin(11, Pin.OUT, value=0)
right = PWM(Pin(14, Pin.OUT, value=0), freq=20833, duty_u16=0)
left = PWM(Pin(15, Pin.OUT, value=0), freq=20833, duty_u16=0)
print("R made", [mem32[CH7_TOP], mem32[CH7_DIV], mem32[CH7_CC], mem32[CH7_CSR] & 1])
mem32[CH7_TOP] = SPEEDS - 1
mem32[CH7_DIV] = 16


def set_speeds(lft, r):
    left_dir.value(lft < 0)
    right_dir.value(r < 0)
    mem32[CH7_CC] = (abs(lft) << 16) | abs(r)


set_speeds(3000, 4500)
print("R regs", [mem32[CH7_TOP], mem32[CH7_DIV], hex(mem32[CH7_CC]), mem16[CH7_CC], mem16[CH7_CC + 2]])
print("R pwm", [left.duty_u16(), right.duty_u16(), left.freq(), right.freq()])
print("R unknown", [mem32[0x40058000], mem32[0x40058000]])
mem32[0x40058000] = 0x1234
print("R unknown_back", mem32[0x40058000])
time.sleep_ms(1000)
mem32[CH7_CSR + 0x3000] = 1  # (the CLR alias: EN cleared, the slice stopped)
print("R stopped", [mem32[CH7_CSR] & 1, mem32[PWM_BASE + 0xA0] >> 7 & 1, left.duty_u16()])
mem32[PWM_BASE + 0xA0 + 0x2000] = 1 << 7  # (EN's SET alias: running again)
mem16[CH7_TOP] = SPEEDS - 1  # (a 16-bit write, copied across the word: TOP keeps 16 bits)
print("R running", [mem32[CH7_CSR] & 1, mem32[CH7_TOP]])
set_speeds(0, 0)
right.duty_u16(32768)  # (the other way: PWM writes the registers)
print("R from_pwm", [hex(mem32[CH7_CC]), mem32[CH7_TOP]])
right.freq(1000)
print("R freq_regs", [mem32[CH7_TOP], mem32[CH7_DIV], right.freq(), right.duty_u16()])
