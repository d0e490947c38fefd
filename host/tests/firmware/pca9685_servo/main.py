# The PCA9685 driver published on PyPI (micropython-pca9685, unchanged, from build/drivers/)
# with its servo helper, set up as its examples show: a servo on channel 0 to 90 degrees,
# then to 30.
import time
from machine import I2C, Pin

from micropython_pca9685 import pca9685
from micropython_pca9685.motor import Servo

i2c = I2C(0, sda=Pin(21), scl=Pin(22))
pca = pca9685.PCA9685(i2c)
pca.frequency = 50
servo = Servo(pca.channels[0])

servo.angle = 90
time.sleep_ms(1000)
print("R at_90", time.ticks_ms())
servo.angle = 30
time.sleep_ms(1000)
print("R frequency", pca.frequency)
print("R angle", servo.angle)
