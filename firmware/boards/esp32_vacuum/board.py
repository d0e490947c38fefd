# ESP32-DevKitC (ESP32-WROOM-32) in RoboClean, the vacuum cleaner robot of seed 003 (which
# used an Arduino Mega): an L298N dual H-bridge for the two TT gear motors, F249 slotted-disk
# IR speed sensors on the wheels, an HC-SR04 on an SG90 servo at the front, and spare GPIOs
# as logic-analyser probes for the scheduler's tasks.
from micropython import const

NAME = "esp32-vacuum"
MOTOR_L_IN1 = const(26)  # L298N IN1/IN2, ENA
MOTOR_L_IN2 = const(27)
MOTOR_L_PWM = const(25)
MOTOR_R_IN1 = const(16)  # IN3/IN4, ENB
MOTOR_R_IN2 = const(17)
MOTOR_R_PWM = const(4)
ENC_L = const(34)  # input only, no pulls: the LM393 module drives it
ENC_R = const(35)
SONAR_TRIG = const(5)
SONAR_ECHO = const(18)  # 5 V ECHO through a 1k/2k divider
SERVO_PWM = const(13)
QUANTUM_PROBE = const(15)  # toggles every 50 ms quantum
POSE_PROBE = const(19)  # toggles at each pose update (100 ms)
SENSE_PROBE = const(21)  # toggles at each sensing task (150 ms)
BEHAVIOUR_PROBE = const(22)  # toggles at each behaviour check (500 ms)
PING_PROBE = const(23)  # high while a ping is measured
