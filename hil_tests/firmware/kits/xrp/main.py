# An XRP's first mission: 25 cm straight by the encoders, a quarter turn left by the gyro,
# then on until the rangefinder sees the wall 15 cm ahead. Each step prints what the
# robot thinks it did (the test holds it to what the plant says happened).
import sys

from xrpkit.defaults import drivetrain, rangefinder

print("board", sys.implementation._machine)
print("straight_cm", drivetrain.straight(25))
print("turned_deg", drivetrain.turn(90))
print("wall_cm", drivetrain.until_near(rangefinder, 15))
print("done")
