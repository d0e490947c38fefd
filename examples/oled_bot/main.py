# oled_bot: an ESP32 two-wheel robot with an I2C bus of three chips: an LSM6DSOX IMU
# (0x6A) to turn by angle, a VL53L0X time-of-flight ranger (0x29) to stop at a wall, and
# an SSD1306 OLED (0x3C, 128x64) showing its state. It turns 90 degrees left on the
# integrated gyro, drives ahead until the wall is 250 mm away, stops, and says so.
import time

import framebuf
from machine import I2C, PWM, Pin

i2c = I2C(0, scl=Pin(22), sda=Pin(21), freq=400_000)
IMU, TOF, OLED = 0x6A, 0x29, 0x3C
TURN_DEG = 90
STOP_MM = 250
GYRO_DPS = 0.070  # per count at 2000 deg/s full scale

ain1, ain2 = Pin(17, Pin.OUT), Pin(18, Pin.OUT)
bin1, bin2 = Pin(23, Pin.OUT), Pin(19, Pin.OUT)
pwm_a, pwm_b = PWM(Pin(16), freq=20_000, duty_u16=0), PWM(Pin(4), freq=20_000, duty_u16=0)


def motors(left, right):
    """Each side's duty from -65535 (back) to 65535 (ahead)."""
    for in1, in2, pwm, duty in ((ain1, ain2, pwm_a, left), (bin1, bin2, pwm_b, right)):
        in1.value(1 if duty > 0 else 0)
        in2.value(1 if duty < 0 else 0)
        pwm.duty_u16(min(65535, abs(duty)))


class Oled:
    """An SSD1306 128x64 on I2C: a MONO_VLSB frame buffer sent whole by show()."""

    def __init__(self):
        self.buf = bytearray(128 * 64 // 8)
        self.fb = framebuf.FrameBuffer(self.buf, 128, 64, framebuf.MONO_VLSB)
        for cmd in (0xAE, 0x20, 0x00, 0x40, 0xA1, 0xA8, 63, 0xC8, 0xD3, 0, 0xDA, 0x12, 0x8D, 0x14, 0xAF):
            i2c.writeto(OLED, bytes((0x80, cmd)))

    def show(self, *lines):
        self.fb.fill(0)
        for row, text in enumerate(lines):
            self.fb.text(text, 0, row * 12, 1)
        for cmd in (0x21, 0, 127, 0x22, 0, 7):
            i2c.writeto(OLED, bytes((0x80, cmd)))
        i2c.writevto(OLED, (b"\x40", self.buf))


def gyro_z_dps():
    raw = i2c.readfrom_mem(IMU, 0x26, 2)  # OUTZ_L_G, OUTZ_H_G
    value = raw[0] | raw[1] << 8
    return (value - 65536 if value & 0x8000 else value) * GYRO_DPS


def range_mm():
    while not i2c.readfrom_mem(TOF, 0x13, 1)[0] & 0x07:  # RESULT_INTERRUPT_STATUS
        time.sleep_ms(2)
    mm = int.from_bytes(i2c.readfrom_mem(TOF, 0x1E, 2), "big")
    i2c.writeto_mem(TOF, 0x0B, b"\x01")  # SYSTEM_INTERRUPT_CLEAR
    return mm


def turn(degrees):
    turned = 0.0
    last = time.ticks_us()
    motors(-30_000, 30_000)
    while turned < degrees:
        time.sleep_ms(5)
        now = time.ticks_us()
        turned += gyro_z_dps() * time.ticks_diff(now, last) / 1e6
        last = now
    motors(0, 0)
    return turned


def main():
    if i2c.readfrom_mem(IMU, 0x0F, 1)[0] != 0x6C or i2c.readfrom_mem(TOF, 0xC0, 1)[0] != 0xEE:
        print("oled_bot: chips missing, found", [hex(a) for a in i2c.scan()])
        return
    oled = Oled()
    i2c.writeto_mem(IMU, 0x11, b"\x5c")  # CTRL2_G: 208 Hz, 2000 deg/s
    i2c.writeto_mem(TOF, 0x00, b"\x02")  # back-to-back ranging
    oled.show("oled_bot", "TURN %d" % TURN_DEG)
    print("oled_bot: turning")
    turned = turn(TURN_DEG)
    print("oled_bot: turned %.1f" % turned)
    mm = range_mm()
    oled.show("oled_bot", "DRIVE", "wall %d mm" % mm)
    print("oled_bot: driving, wall at", mm)
    motors(35_000, 35_000)
    shown = time.ticks_ms()
    while mm > STOP_MM:
        mm = range_mm()
        if time.ticks_diff(time.ticks_ms(), shown) >= 500:
            oled.show("oled_bot", "DRIVE", "wall %d mm" % mm)
            shown = time.ticks_ms()
    motors(0, 0)
    oled.show("oled_bot", "STOP", "wall %d mm" % mm)
    print("oled_bot: stopped at", mm)


main()
while True:  # (done: it stays where it stopped)
    time.sleep_ms(1000)
