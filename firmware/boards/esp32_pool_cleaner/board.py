# ESP32-DevKitC in the WEDA B400 pool cleaner (seeds 000/001): two relay drivers stop
# the left and right tracks (the thesis PC's parallel-port bits 1 and 0), two bumper
# micro-switches closing to ground (front = bumper1, rear = bumper2), and the two side
# NAVMAN 100 sounders' NMEA 0183 output (RS-232 through a MAX3232) on UART2, with a
# multiplexer select line (bit 2). A spare GPIO is the logic-analyser probe.
from micropython import const

NAME = "esp32-pool-cleaner"
TRACK_L_STOP = const(26)  # 1 stops the left track
TRACK_R_STOP = const(27)  # 1 stops the right track
BUMPER_FRONT = const(32)  # bumper1, closes to ground, internal pull-up
BUMPER_REAR = const(33)  # bumper2
SONAR_UART = const(2)  # UART2: RX on GPIO16 (TX GPIO17 unused), 4800 8N1
SONAR_SELECT = const(25)  # 0: left sounder (sonar 0), 1: right
LOOP_PROBE = const(15)  # toggles once per 50 ms control quantum
