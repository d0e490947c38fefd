# Every mapped part on an ESP32 DevKitC: a button's IRQ toggles the LED, the servo goes to
# 90 degrees, the HC-SR04 ranges, the ADCs read a knob and a light sensor, the OLED shows
# text, the ring shows two colours, the IMU is read over I2C; results printed as "key value".
import time

import neopixel
import ssd1306
from machine import ADC, I2C, PWM, Pin, time_pulse_us

led = Pin(13, Pin.OUT, value=0)
presses = 0


def pressed(pin):
    global presses
    presses += 1
    led.value(presses % 2)


button = Pin(4, Pin.IN, Pin.PULL_UP)
button.irq(trigger=Pin.IRQ_FALLING, handler=pressed)

servo = PWM(Pin(18), freq=50)
servo.duty_ns(1_500_000)  # 90 degrees

trig = Pin(5, Pin.OUT, value=0)
echo = Pin(19, Pin.IN)


def distance_cm():
    trig.value(1)
    time.sleep_us(10)
    trig.value(0)
    return time_pulse_us(echo, 1, 30_000) / 58.31


pot = ADC(Pin(34))
ldr = ADC(Pin(35))
dark = Pin(25, Pin.IN)
switch = Pin(26, Pin.IN)
relay = Pin(27, Pin.OUT, value=1)
rgb = [Pin(p, Pin.OUT, value=1) for p in (14, 12, 15)]  # common anode: high is off
rgb[1].value(0)  # green

ring = neopixel.NeoPixel(Pin(23), 12)
ring[0] = (255, 0, 0)
ring[11] = (0, 0, 255)
ring.write()

i2c = I2C(0, scl=Pin(22), sda=Pin(21), freq=400_000)
i2c.writeto_mem(0x68, 0x6B, b"\x00")  # wake the MPU6050
time.sleep_ms(10)


def signed(data, i):
    v = data[i] << 8 | data[i + 1]
    return v - 65536 if v > 32767 else v


raw = i2c.readfrom_mem(0x68, 0x3B, 14)
print("accel_z_g", signed(raw, 4) / 16384)
print("gyro_z_dps", signed(raw, 12) / 131)

oled = ssd1306.SSD1306_I2C(128, 64, i2c)
oled.text("Hello Wokwi", 0, 0)
oled.show()

print("distance_cm", distance_cm())
print("pot_u16", pot.read_u16())
print("ldr_u16", ldr.read_u16())
print("dark", dark.value())
print("switch", switch.value())
print("ready")
probe = Pin(2, Pin.OUT)
while True:
    probe.value(not probe.value())
    time.sleep_ms(10)
