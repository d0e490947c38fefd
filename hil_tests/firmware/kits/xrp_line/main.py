# An XRP following a line, as the XRP curriculum teaches it: once the button is pressed,
# the two reflectance channels (0.0 white .. 1.0 black) say which side the line is on,
# and a proportional-derivative correction on their difference steers the wheels' efforts.
# The board support is xrpkit (XRPLib's style); the test draws the course.
import time

from xrpkit.defaults import board, drivetrain, reflectance

BASE_EFFORT = 0.6
KP = 0.6  # effort per unit of (left - right)
KD = 0.01  # effort per unit of (left - right) a second
PERIOD_MS = 10
LOST = 0.3  # both channels paler than this: off the line

board.set_rgb((0, 0, 32))
board.wait_for_button()
print("start", reflectance.get_left(), reflectance.get_right())
board.set_rgb((0, 32, 0))
last_error = 0.0
lost = False
report = time.ticks_add(time.ticks_ms(), 1000)
while True:
    left, right = reflectance.get_left(), reflectance.get_right()
    error = left - right  # > 0: the line is to the left
    rate = (error - last_error) * 1000 / PERIOD_MS
    last_error = error
    turn = KP * error + KD * rate
    drivetrain.set_effort(BASE_EFFORT - turn, BASE_EFFORT + turn)
    if (max(left, right) < LOST) != lost:
        lost = not lost
        print("lost" if lost else "found", time.ticks_ms())
    if time.ticks_diff(time.ticks_ms(), report) >= 0:
        report = time.ticks_add(report, 1000)
        print("cm", drivetrain.distance_cm())
    time.sleep_ms(PERIOD_MS)
