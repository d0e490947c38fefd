# A 3pi+ 2040 line follower in the style of Pololu's line_follower.py demo (written here,
# not copied): the display says what it does, button B (BOOTSEL) starts it, the robot
# sweeps left and right over the line while the line sensors calibrate, then a PD
# correction on the line's position (0 .. 4000 under the five sensors, 2000 centred) steers
# the wheels. The RGB LEDs say the phase: yellow calibrating, green following, red lost.
# The board support is the kitbot package (lib/kitbot: the motors on PWM slice 7 through
# mem32, the SH1106 and the APA102 LEDs sharing SPI0), the line sensors ir_sensors.py.
import time
from micropython import const

from ir_sensors import LineSensors
from kitbot.buttons import bootsel_pressed
from kitbot.display import Display
from kitbot.motors import Motors
from kitbot.rgb_leds import RGBLEDs

MAX_SPEED = const(4500)  # of the motors' 6000
CALIBRATION_SPEED = const(1500)
KP = 3  # speed per unit of position error ...
KD = 20  # ... and of its change since the last read

display = Display()
motors = Motors()
line_sensors = LineSensors()
leds = RGBLEDs(count=6)


def light(rgb):
    for led in range(6):
        leds.set(led, rgb)
    leds.show()


light((0, 0, 0))  # (as the library's RGBLEDs() does: its show() takes GP6 back from the SPI)

display.fill(0)
display.text("Line Follower", 0, 0)
display.text("Place on line", 0, 20)
display.text("and press B.", 0, 30)
display.show()
while not bootsel_pressed():
    time.sleep_ms(10)
while bootsel_pressed():
    time.sleep_ms(10)

print("start", list(line_sensors.read()))  # (on the line, still: the raw discharge times)
light((255, 160, 0))
for speed, ms in ((CALIBRATION_SPEED, 200), (-CALIBRATION_SPEED, 400), (CALIBRATION_SPEED, 200)):
    motors.set_speeds(speed, -speed)
    end = time.ticks_add(time.ticks_ms(), ms)
    while time.ticks_diff(end, time.ticks_ms()) > 0:
        line_sensors.calibrate(reads=1)
motors.off()
print("calibrated", list(line_sensors.cal_min), list(line_sensors.cal_max))
light((0, 255, 0))

p = 0
lost = False
while True:
    line = line_sensors.read_calibrated()
    last_p = p
    if line[1] < 700 and line[2] < 700 and line[3] < 700:  # off the line: it was last seen to that side
        if not lost:
            print("lost", time.ticks_ms())
            light((255, 0, 0))
        lost = True
        p = -2000 if p < 0 else 2000
    else:
        if lost:
            print("found", time.ticks_ms())
            light((0, 255, 0))
        lost = False
        p = (1000 * line[1] + 2000 * line[2] + 3000 * line[3] + 4000 * line[4]) // sum(line) - 2000
    pid = KP * p + KD * (p - last_p)  # p > 0: the line is to the right
    left = max(0, min(MAX_SPEED, MAX_SPEED + pid))
    right = max(0, min(MAX_SPEED, MAX_SPEED - pid))
    motors.set_speeds(left, right)
    time.sleep_ms(10)
