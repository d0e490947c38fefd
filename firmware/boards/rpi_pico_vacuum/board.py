# Raspberry Pi Pico (RP2040) in RoboClean, the vacuum cleaner robot of seed 003: an L298N
# dual H-bridge, F249 slotted-disk IR speed sensors, an HC-SR04 on an SG90 servo, and spare
# GPIOs as logic-analyser probes. ENA, ENB and the servo sit on three different PWM slices
# (2A, 4A, 0A), so the servo's 50 Hz does not set the motors' frequency.
from micropython import const

NAME = "rpi-pico-vacuum"
MOTOR_L_IN1 = const(2)
MOTOR_L_IN2 = const(3)
MOTOR_L_PWM = const(4)
MOTOR_R_IN1 = const(6)
MOTOR_R_IN2 = const(7)
MOTOR_R_PWM = const(8)
ENC_L = const(10)
ENC_R = const(11)
SONAR_TRIG = const(14)
SONAR_ECHO = const(15)  # 5 V ECHO through a 1k/2k divider
SERVO_PWM = const(16)
QUANTUM_PROBE = const(18)
POSE_PROBE = const(19)
SENSE_PROBE = const(20)
BEHAVIOUR_PROBE = const(21)
PING_PROBE = const(22)
