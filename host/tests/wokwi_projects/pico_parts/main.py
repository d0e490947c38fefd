# Every mapped part on a Raspberry Pi Pico: a button's IRQ (to 3V3, on a pull-down) counts
# presses, the LED is a PWM, the servo goes to 45 degrees, two HC-SR04s range, three ADCs
# read, the OLED shows text, the matrix and the pixel show colours, the IMU (at 0x69) is
# read over I2C0; results printed as "key value".
import time

import neopixel
import ssd1306
from machine import ADC, I2C, PWM, Pin, time_pulse_us

presses = 0


def pressed(pin):
    global presses
    presses += 1
    print("press", presses, time.ticks_ms())


button = Pin(15, Pin.IN, Pin.PULL_DOWN)
button.irq(trigger=Pin.IRQ_RISING, handler=pressed)

led = PWM(Pin(16), freq=1000, duty_u16=16384)
servo = PWM(Pin(22), freq=50)
servo.duty_ns(1_000_000)  # 45 degrees on a 500..2500 us servo


def distance_cm(trig, echo):
    trig.value(1)
    time.sleep_us(10)
    trig.value(0)
    return time_pulse_us(echo, 1, 30_000) / 58.31


sonars = [(Pin(2, Pin.OUT, value=0), Pin(3, Pin.IN)), (Pin(12, Pin.OUT, value=0), Pin(13, Pin.IN))]
pot, ldr, slide = ADC(26), ADC(Pin(27)), ADC(28)
dark = Pin(14, Pin.IN)
switch = Pin(10, Pin.IN)
relay = Pin(11, Pin.OUT, value=0)  # a PNP module: low pulls it in
rgb = [Pin(p, Pin.OUT, value=0) for p in (6, 7, 8)]
rgb[0].value(1)
rgb[2].value(1)  # magenta

matrix = neopixel.NeoPixel(Pin(9), 8)
matrix[7] = (0, 255, 0)
matrix.write()
pixel = neopixel.NeoPixel(Pin(18), 1)
pixel[0] = (10, 20, 30)
pixel.write()

i2c = I2C(0, sda=Pin(4), scl=Pin(5))
i2c.writeto_mem(0x69, 0x6B, b"\x00")
time.sleep_ms(10)
raw = i2c.readfrom_mem(0x69, 0x3F, 2)
az = raw[0] << 8 | raw[1]
print("accel_z_g", (az - 65536 if az > 32767 else az) / 16384)
print("who_am_i", i2c.readfrom_mem(0x69, 0x75, 1)[0])

oled = ssd1306.SSD1306_I2C(128, 64, i2c)
oled.text("Pico OK", 0, 8)
oled.show()

for i, (trig, echo) in enumerate(sonars):
    print("distance_cm", i, distance_cm(trig, echo))
print("pot_u16", pot.read_u16())
print("slide_u16", slide.read_u16())
print("ldr_u16", ldr.read_u16())
print("dark", dark.value())
print("switch", switch.value())
print("ready")
probe = Pin(17, Pin.OUT)
while True:
    probe.value(not probe.value())
    time.sleep_ms(20)
