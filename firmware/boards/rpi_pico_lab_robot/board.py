# Raspberry Pi Pico (RP2040) on the dead-reckoning lab robot (seed 004): a DRV8833 dual
# bridge (two PWM inputs per motor, one PWM slice per motor), two quadrature wheel
# encoders with both channels on interrupts, three MaxBotix LV-EZ analog sonars (front,
# left, left 45 degrees) on the Pico's three ADC inputs with their RX lines tied to one
# GPIO, the program jumper, and a spare GPIO as a logic-analyser probe.
from micropython import const

NAME = "rpi-pico-lab-robot"
MOTOR_L_IN1 = const(2)  # PWM slice 1 A
MOTOR_L_IN2 = const(3)  # PWM slice 1 B
MOTOR_R_IN1 = const(4)  # PWM slice 2 A
MOTOR_R_IN2 = const(5)  # PWM slice 2 B
ENC_L_A = const(10)
ENC_L_B = const(11)
ENC_R_A = const(12)
ENC_R_B = const(13)
SONAR_F_ADC = const(26)  # ADC0
SONAR_L_ADC = const(27)  # ADC1
SONAR_LF_ADC = const(28)  # ADC2
SONAR_RX = const(14)  # the three sonars' RX: high for 20 us starts a ranging
PROGRAM_JUMPER = const(15)  # to ground: wall following; open (pull-up): square path
LOOP_PROBE = const(16)  # toggles once per control step
