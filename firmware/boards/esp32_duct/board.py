# ESP32-DevKitC in seed 002's duct inspection robot (which used an ATmega128 "Roboaudiostix"):
# two LMD18200 bridges (DIR + PWM, through optocouplers), the two slotted-disk
# interrupters on the motor shafts, the three amplitude sonars' peak detectors on ADC1,
# the master link on UART2 and a spare GPIO as a logic-analyser probe.
from micropython import const

NAME = "esp32-duct"
MOTOR_L_DIR = const(26)
MOTOR_L_PWM = const(25)
MOTOR_R_DIR = const(16)
MOTOR_R_PWM = const(4)
ENC_L = const(34)  # input only: the comparator drives it
ENC_R = const(35)
SONAR_F_ADC = const(36)  # ADC1_CH0
SONAR_L_ADC = const(39)  # ADC1_CH3
SONAR_R_ADC = const(32)  # ADC1_CH4
LINK_UART = const(2)  # TX 17, RX 5 (16 drives the right DIR)
LOOP_PROBE = const(15)  # toggles at every speed-loop run (50 ms)
