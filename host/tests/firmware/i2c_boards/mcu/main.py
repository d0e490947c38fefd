# The MCU: an I2C target at 0x42 with a 16-byte register file; its loop counts in registers
# 0..1 every 5 ms; a command written to register 8 is said by its END_WRITE handler.
import time
from machine import I2CTarget

regs = bytearray(16)
seen = []


def on_i2c(target):
    flags = target.irq().flags()
    if flags & I2CTarget.IRQ_END_WRITE:
        seen.append((target.memaddr, regs[8], time.ticks_us()))


target = I2CTarget(0, 0x42, mem=regs)
target.irq(on_i2c)
count = 0
while True:
    count += 1
    regs[0] = count & 0xFF
    regs[1] = count >> 8
    while seen:
        addr, value, t = seen.pop(0)
        print("mcu command", value, "at reg", addr, "at", t)
    time.sleep_ms(5)
