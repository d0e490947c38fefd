# An XRP's first mission, once its button is pressed: 25 cm straight by the encoders, a
# quarter turn left by the gyro, then on until the rangefinder sees the wall 15 cm ahead. Each step prints what the
# robot thinks it did (the test holds it to what the plant says happened).
import sys

from xrpkit.defaults import board, drivetrain, rangefinder, reflectance, servo_one, servo_two

print("board", sys.implementation._machine)
servo_one.set_angle(90)
servo_two.set_angle(0)
board.set_rgb((0, 0, 32))
board.wait_for_button()
print("floor", reflectance.get_left(), reflectance.get_right())
board.set_rgb((0, 32, 0))
print("straight_cm", drivetrain.straight(25))
print("turned_deg", drivetrain.turn(90))
print("wall_cm", drivetrain.until_near(rangefinder, 15))
board.set_rgb((32, 0, 0))
print("done")
