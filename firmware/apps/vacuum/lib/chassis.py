# RoboClean's measured numbers: one place for each (seed 003 gives only symbols: R, L, N,
# PWMmin, PWMmax, Vmax...; the values are the robot as built here, docs/vacuum.md).
# Lengths in cm, speeds in cm/s, turn rates in rad/s, PWM on the Arduino's 0..255 scale.

WHEEL_DIAMETER_CM = 6.5  # the usual wheel of a TT gear motor
SLOTS = 20  # numberOfHole: the disk sold with the F249 module; rising edges counted
TRACK_CM = 18.0  # L, d_baseline: wheel centre to wheel centre
BODY_RADIUS_CM = 12.5  # the 25 cm disc (Table 3.2)
SENSOR_X_CM = 10.0  # the servo's axis, ahead of the axle on the centre line (X_s; Y_s = 0)

V_CRUISE = 15.0  # V: A.3 never assigns it; a constant cruise speed
V_MAX = 30.0  # Vmax: either wheel
V_MAX_W0 = V_MAX  # top speed when W = 0
W_MAX_V0 = 2 * V_MAX / TRACK_CM  # top turn rate when V = 0 (one wheel back, one forward)

# map(V, robotMinSpeed, robotMaxSpeed, PWMmin, PWMmax): two points of the wheel speed
# against analogWrite() measured on the robot (8 cm/s at 107, 30 cm/s at 228); the line
# through them meets 0 cm/s at about 64, where the motor stalls ("at low speed the motor
# was not able to supply the required torque", §5.2).
ROBOT_MIN_SPEED = 8
ROBOT_MAX_SPEED = 30
PWM_MIN = 107
PWM_MAX = 228
PWM_FULL = 255
