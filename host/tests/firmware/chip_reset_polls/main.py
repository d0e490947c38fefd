# Resets an LSM6DSOX-class IMU and an LIS3MDL-class compass as public drivers do: set the
# self-clearing bit, then read the register until the chip clears it (no sleep between
# reads). Each wait is timed; then the compass, left powered down (CTRL_REG3 at its reset
# value), is polled for data ready, which never comes: the loop gives up after 3 s.
import time
from machine import I2C, Pin

IMU, MAG = 0x6A, 0x1C
CTRL3_C = 0x12
CTRL_REG2, STATUS_REG = 0x21, 0x27
GIVE_UP_US = 3_000_000

i2c = I2C(0, sda=Pin(21), scl=Pin(22), freq=400_000)


def reg(address, register):
    return i2c.readfrom_mem(address, register, 1)[0]


def wait_clear(name, address, register, bit):
    i2c.writeto_mem(address, register, bytes((reg(address, register) | bit,)))
    t0 = time.ticks_us()
    polls = 0
    while reg(address, register) & bit:
        polls += 1
        if time.ticks_diff(time.ticks_us(), t0) > GIVE_UP_US:
            print("R", name + "_us", None)
            return
    print("R", name + "_us", time.ticks_diff(time.ticks_us(), t0))
    print("R", name + "_polls", polls)


i2c.writeto_mem(IMU, 0x10, b"\x40")  # CTRL1_XL: 104 Hz (kept by BOOT, undone by SW_RESET)
wait_clear("boot", IMU, CTRL3_C, 0x80)
print("R after_boot", reg(IMU, 0x10))
wait_clear("sw_reset", IMU, CTRL3_C, 0x01)
print("R after_sw_reset", reg(IMU, 0x10))
wait_clear("reboot", MAG, CTRL_REG2, 0x08)
wait_clear("soft_rst", MAG, CTRL_REG2, 0x04)

t0 = time.ticks_us()
reads = 0
while not reg(MAG, STATUS_REG) & 0x08:  # ZYXDA: never, the compass is powered down
    reads += 1
    if time.ticks_diff(time.ticks_us(), t0) > GIVE_UP_US:
        break
print("R gave_up_after", reads)
