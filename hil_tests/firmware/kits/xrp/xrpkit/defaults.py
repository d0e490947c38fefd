# The robot's parts as the board has them, picked by the board's name (RP2350 controller or
# RP2040 beta): pin names from the board's own definition.
import sys
from machine import Pin

from .board import Board
from .drive import Drivetrain
from .encoder import Encoder
from .imu import IMU
from .motor import DirSpeedMotor, TwoPwmMotor
from .rangefinder import Rangefinder
from .reflectance import Reflectance
from .servo import Servo

RP2350 = "RP2350" in sys.implementation._machine
if RP2350:
    left_motor = TwoPwmMotor("MOTOR_L_IN_1", "MOTOR_L_IN_2", flip=True)
    right_motor = TwoPwmMotor("MOTOR_R_IN_1", "MOTOR_R_IN_2")
else:
    left_motor = DirSpeedMotor("MOTOR_L_IN_1", "MOTOR_L_IN_2", flip=True)
    right_motor = DirSpeedMotor("MOTOR_R_IN_1", "MOTOR_R_IN_2")
left_encoder = Encoder(0, "MOTOR_L_ENCODER_A", "MOTOR_L_ENCODER_B", flip=True)
right_encoder = Encoder(1, "MOTOR_R_ENCODER_A", "MOTOR_R_ENCODER_B")
imu = IMU()
rangefinder = Rangefinder("DISTANCE_TRIGGER", "DISTANCE_ECHO")
reflectance = Reflectance("LINE_L", "LINE_R")
servo_one = Servo("SERVO_1")
servo_two = Servo("SERVO_2")
board = Board("BOARD_USER_BUTTON", rgb_pin=getattr(Pin.board, "BOARD_NEOPIXEL", None))  # (the RP2350's)
drivetrain = Drivetrain(left_motor, right_motor, left_encoder, right_encoder, imu)
