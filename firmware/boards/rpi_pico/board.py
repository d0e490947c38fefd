# Raspberry Pi Pico (RP2040) pin map for the rover: a TB6612FNG dual H-bridge, two
# quadrature wheel encoders, a MaxBotix LV-EZ analog sonar on ADC0, a front bumper
# switch to ground, and a spare GPIO as a timing probe for a logic analyser.
from micropython import const

NAME = "rpi-pico"
MOTOR_L_IN1 = const(2)
MOTOR_L_IN2 = const(3)
MOTOR_L_PWM = const(4)
MOTOR_R_IN1 = const(6)
MOTOR_R_IN2 = const(7)
MOTOR_R_PWM = const(8)
ENC_L_A = const(10)
ENC_L_B = const(11)
ENC_R_A = const(12)
ENC_R_B = const(13)
SONAR_ADC = const(26)  # ADC0
BUMPER = const(15)  # closes to ground, internal pull-up
LOOP_PROBE = const(16)  # toggles once per control step
