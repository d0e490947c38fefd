# ESP32-DevKitC on the dead-reckoning lab robot (seed 004): a DRV8833 dual bridge (two
# PWM inputs per motor), two quadrature wheel encoders with both channels on interrupts,
# three MaxBotix LV-EZ analog sonars (front, left, left 45 degrees) on ADC1 with their RX
# lines tied to one GPIO, the program jumper, and a spare GPIO as a logic-analyser probe.
from micropython import const

NAME = "esp32-lab-robot"
MOTOR_L_IN1 = const(25)  # DRV8833 AIN1
MOTOR_L_IN2 = const(26)  # AIN2
MOTOR_R_IN1 = const(27)  # BIN1
MOTOR_R_IN2 = const(14)  # BIN2
ENC_L_A = const(18)
ENC_L_B = const(19)
ENC_R_A = const(21)
ENC_R_B = const(22)
SONAR_F_ADC = const(36)  # ADC1_CH0 (VP); GPIO34..39 are inputs only
SONAR_L_ADC = const(39)  # ADC1_CH3 (VN)
SONAR_LF_ADC = const(34)  # ADC1_CH6; ADC2 is unusable while Wi-Fi runs
SONAR_RX = const(23)  # the three sonars' RX: high for 20 us starts a ranging
PROGRAM_JUMPER = const(16)  # to ground: wall following; open (pull-up): square path
LOOP_PROBE = const(17)  # toggles once per control step
