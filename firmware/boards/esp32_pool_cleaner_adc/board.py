# ESP32-DevKitC in the WEDA B400 pool cleaner, ADC sonar build (the design card's
# option): the two side sounders give 0.33 V per metre on ADC1 inputs instead of
# NMEA sentences on a UART; no select line. Tracks, bumpers and probe as on
# esp32_pool_cleaner.
from micropython import const

NAME = "esp32-pool-cleaner-adc"
TRACK_L_STOP = const(26)  # 1 stops the left track
TRACK_R_STOP = const(27)  # 1 stops the right track
BUMPER_FRONT = const(32)  # bumper1, closes to ground, internal pull-up
BUMPER_REAR = const(33)  # bumper2
SONAR_L_ADC = const(34)  # ADC1_CH6, input only
SONAR_R_ADC = const(35)  # ADC1_CH7, input only
LOOP_PROBE = const(15)  # toggles once per 50 ms control quantum
