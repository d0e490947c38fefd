# Busy waits as drivers and menus write them, each reading until its answer comes or 1.1 s
# have passed (with a short sleep between reads, or none): a button a person presses at 0.5 s (a wait that ends), a pin
# nothing drives, the RP2040's SIO GPIO_IN and a word of SRAM through machine.mem32, and a
# compass's data-ready bit while it is powered down (waits that never end). On an ESP32, a
# button nobody presses and the GPIO_IN_REG word through machine.mem32.
import sys
import time
from machine import I2C, Pin, mem32

GIVE_UP_US = 1_100_000


def spin(name, read, want=None, pause_us=50):
    t0 = time.ticks_us()
    reads = 0
    while True:
        answer = read()
        reads += 1
        if answer == want or time.ticks_diff(time.ticks_us(), t0) > GIVE_UP_US:
            break
        if pause_us:
            time.sleep_us(pause_us)
    print("R", name, [answer, reads, time.ticks_diff(time.ticks_us(), t0)])


if sys.platform == "rp2":
    button = Pin(2, Pin.IN, Pin.PULL_UP)
    spin("button", button.value, 0, 20)
    idle = Pin(6, Pin.IN, Pin.PULL_UP)
    spin("idle", idle.value)
    spin("gpio_in", lambda: mem32[0xD0000004] >> 6 & 1)  # SIO GPIO_IN, GPIO6's bit
    spin("sram", lambda: mem32[0x20001000])
    i2c = I2C(0, sda=Pin(16), scl=Pin(17), freq=400_000)
    spin("zyxda", lambda: i2c.readfrom_mem(0x1C, 0x27, 1)[0] & 0x08, None, 0)  # LIS3MDL STATUS_REG
else:
    stop = Pin(4, Pin.IN, Pin.PULL_UP)
    spin("stop", stop.value, 0)
    spin("gpio_in_reg", lambda: mem32[0x3FF4403C])  # the ESP32's GPIO_IN_REG
