# ESP32-DevKitC (ESP32-WROOM-32) pin map for the rover: a TB6612FNG dual H-bridge,
# two quadrature wheel encoders, a MaxBotix LV-EZ analog sonar on ADC1, a front
# bumper switch to ground, and a spare GPIO as a timing probe for a logic analyser.
from micropython import const

NAME = "esp32-devkitc"
MOTOR_L_IN1 = const(26)
MOTOR_L_IN2 = const(27)
MOTOR_L_PWM = const(25)
MOTOR_R_IN1 = const(16)
MOTOR_R_IN2 = const(17)
MOTOR_R_PWM = const(4)
ENC_L_A = const(34)  # GPIO34..39 are input-only with no pulls: the encoders drive them
ENC_L_B = const(35)
ENC_R_A = const(36)
ENC_R_B = const(39)
SONAR_ADC = const(32)  # ADC1_CH4; ADC2 is unusable while Wi-Fi runs
BUMPER = const(23)  # closes to ground, internal pull-up
LOOP_PROBE = const(15)  # toggles once per control step
