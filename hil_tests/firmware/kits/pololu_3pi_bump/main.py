# A 3pi+ 2040 drives until its bumper meets a wall, in the style of Pololu's wall_bumper.py
# demo (written here, not copied): the bump sensors calibrate while it stands, button B
# (BOOTSEL) starts it, and it stops as soon as a flap is pressed, saying which and the
# reads, the RGB LEDs red on that side. The bump sensors are ../pololu_3pi_line's
# ir_sensors.py (copied beside this file by the test), the motors and the LEDs the kitbot
# package's.
import time

from ir_sensors import BumpSensors
from kitbot.buttons import bootsel_pressed
from kitbot.motors import Motors
from kitbot.rgb_leds import RGBLEDs

motors = Motors()
leds = RGBLEDs(count=6)
bump_sensors = BumpSensors()
leds.show()  # (all off; as the library's RGBLEDs() does, its show() takes GP6 back from the SPI)
bump_sensors.calibrate(count=10)
print("thresholds", list(bump_sensors.threshold_min), list(bump_sensors.threshold_max))
while not bootsel_pressed():
    time.sleep_ms(10)
while bootsel_pressed():
    time.sleep_ms(10)

motors.set_speeds(3000, 3000)
while True:
    data = bump_sensors.read()
    if bump_sensors.left_is_pressed() or bump_sensors.right_is_pressed():
        break
    time.sleep_ms(5)
motors.off()
left, right = bump_sensors.left_is_pressed(), bump_sensors.right_is_pressed()
for led in range(6):  # LEDs 0..2 on the right of the board, 3..5 on the left (an arrangement of ours)
    on_left = led >= 3
    leds.set(led, (255, 0, 0) if (left and on_left) or (right and not on_left) else (0, 0, 0))
leds.show()
print("bumped", int(left), int(right), list(data))
