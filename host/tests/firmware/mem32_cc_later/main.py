# Slice 7 set up through its registers alone (no machine.PWM), its pins given to the PWM
# function through IO_BANK0's FUNCSEL, then its duty changed twice through CC, as a motor
# driver does at each new speed: half, full, then stopped, 100 ms each.
import time
from machine import Pin, mem32

CSR = 0x40050000 + 7 * 0x14
DIV, CC, TOP = CSR + 0x04, CSR + 0x0C, CSR + 0x10

Pin(10, Pin.OUT, value=0)
Pin(11, Pin.OUT, value=0)
mem32[TOP] = 5999
mem32[DIV] = 16
mem32[CC] = 3000 << 16 | 3000
mem32[CSR] = 1
for gpio in (14, 15):
    mem32[0x40014000 + 8 * gpio + 4] = 4  # FUNCSEL: PWM
time.sleep_ms(100)
mem32[CC] = 6000 << 16 | 6000
time.sleep_ms(100)
mem32[CC] = 0
print("R funcsel", [mem32[0x40014000 + 8 * gpio + 4] & 0x1F for gpio in (14, 15)])
