# Raspberry Pi Pico (RP2040) in seed 002's duct inspection robot: two LMD18200 bridges
# (DIR + PWM), the slotted-disk interrupters on GPIO interrupts, the three amplitude
# sonars on ADC0-2, the master link on UART0 and a spare GPIO as a probe.
from micropython import const

NAME = "rpi-pico-duct"
MOTOR_L_DIR = const(2)
MOTOR_L_PWM = const(3)  # PWM slice 1 B
MOTOR_R_DIR = const(4)
MOTOR_R_PWM = const(5)  # PWM slice 2 B
ENC_L = const(10)
ENC_R = const(11)
SONAR_F_ADC = const(26)  # ADC0
SONAR_L_ADC = const(27)  # ADC1
SONAR_R_ADC = const(28)  # ADC2
LINK_UART = const(0)  # TX GP0, RX GP1
LOOP_PROBE = const(16)  # toggles at every speed-loop run (50 ms)
