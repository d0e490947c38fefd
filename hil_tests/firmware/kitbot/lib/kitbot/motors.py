# The two motors: DIR+PWM bridges on PWM slice 7 (GP14 channel A: right, GP15 channel B:
# left). machine.PWM gives the pins to the PWM function and starts the slice; then its
# registers are written through mem32 (RP2040 datasheet 4.5.3: CSR, DIV, CTR, CC, TOP at
# 0x14 per slice from 0x40050000) for 6000 steps of speed at 20.8 kHz.
from machine import PWM, Pin, mem32
from micropython import const

_PWM_BASE = const(0x40050000)
_CSR = const(_PWM_BASE + 7 * 0x14)
_DIV = const(_CSR + 0x04)
_CC = const(_CSR + 0x0C)
_TOP = const(_CSR + 0x10)
MAX_SPEED = const(6000)  # TOP + 1: 125 MHz / 1 / 6000 = 20.8 kHz


class Motors:
    def __init__(self):
        self.right_dir = Pin(10, Pin.OUT, value=0)
        self.left_dir = Pin(11, Pin.OUT, value=0)
        self.right_pwm = PWM(Pin(14, Pin.OUT, value=0), freq=20833, duty_u16=0)
        self.left_pwm = PWM(Pin(15, Pin.OUT, value=0), freq=20833, duty_u16=0)
        mem32[_TOP] = MAX_SPEED - 1
        mem32[_DIV] = 1 << 4  # integer divider 1 (8.4 fixed point)
        mem32[_CSR] = 1  # EN, phase-correct off, not inverted

    def set_speeds(self, left, right):
        # forward: DIR low (the kit's bridges); CC = B (left) << 16 | A (right)
        self.left_dir.value(1 if left < 0 else 0)
        self.right_dir.value(1 if right < 0 else 0)
        left = min(abs(left), MAX_SPEED)
        right = min(abs(right), MAX_SPEED)
        mem32[_CC] = left << 16 | right

    def off(self):
        mem32[_CC] = 0

    def registers(self):
        return [mem32[_CSR], mem32[_DIV], mem32[_TOP], mem32[_CC]]
