# The named pins of rp2 boards other than the Pico, as MicroPython's board definitions
# give them (ports/rp2/boards/<BOARD>/pins.csv; the board's name is its mpconfigboard.h
# MICROPY_HW_BOARD_NAME, which begins sys.implementation._machine), and the GPIO count
# (NUM_BANK0_GPIOS: 30, or 48 where the board's mpconfigboard.cmake sets PICO_NUM_GPIOS 48,
# an RP2350B). machine.py looks a board up here by the machine name the host gave it.
# A board with a CYW43 radio has its GPIOs too (pins.csv: LED, WL_GPIO0..2 on EXT_GPIO0..2,
# the radio's, not the chip's; machine_pin_ext_*): they are lines by those names, as the
# BOOTSEL line is (an output that reaches no chip GPIO; a rig file may wire them by name).
_GP30 = {"GP%d" % n: n for n in range(30)}
_CYW43 = {"LED": "EXT_GPIO0", "WL_GPIO0": "EXT_GPIO0", "WL_GPIO1": "EXT_GPIO1", "WL_GPIO2": "EXT_GPIO2"}
_XRP_LED = dict(_CYW43, BOARD_LED="EXT_GPIO0", BRD_LED="EXT_GPIO0")
_XRP_BETA = {
    "MOTOR_L_IN_1": 6, "MOTOR_L_IN_2": 7, "MOTOR_R_IN_1": 14, "MOTOR_R_IN_2": 15,
    "MOTOR_3_IN_1": 2, "MOTOR_3_IN_2": 3, "MOTOR_4_IN_1": 10, "MOTOR_4_IN_2": 11,
    "MOTOR_L_ENCODER_A": 4, "MOTOR_L_ENCODER_B": 5, "MOTOR_R_ENCODER_A": 12, "MOTOR_R_ENCODER_B": 13,
    "MOTOR_3_ENCODER_A": 0, "MOTOR_3_ENCODER_B": 1, "MOTOR_4_ENCODER_A": 8, "MOTOR_4_ENCODER_B": 9,
    "SERVO_1": 16, "SERVO_2": 17, "I2C_SDA_1": 18, "I2C_SCL_1": 19,
    "DISTANCE_TRIGGER": 20, "DISTANCE_ECHO": 21, "LINE_L": 26, "LINE_R": 27,
    "BOARD_VIN_MEASURE": 28, "BOARD_USER_BUTTON": 22,
    "ML_IN_1": 6, "ML_IN_2": 7, "MR_IN_1": 14, "MR_IN_2": 15, "M3_IN_1": 2, "M3_IN_2": 3,
    "M4_IN_1": 10, "M4_IN_2": 11, "ML_ENC_A": 4, "ML_ENC_B": 5, "MR_ENC_A": 12, "MR_ENC_B": 13,
    "M3_ENC_A": 0, "M3_ENC_B": 1, "M4_ENC_A": 8, "M4_ENC_B": 9, "S1": 16, "S2": 17,
    "SDA_1": 18, "SCL_1": 19, "RANGE_TRIGGER": 20, "RANGE_ECHO": 21,
    "REFLECTANCE_L": 26, "REFLECTANCE_R": 27, "BRD_VIN": 28, "BRD_USR_BTN": 22,
}  # fmt: skip
_XRP = {
    "MOTOR_L_IN_1": 34, "MOTOR_L_IN_2": 35, "MOTOR_R_IN_1": 32, "MOTOR_R_IN_2": 33,
    "MOTOR_3_IN_1": 20, "MOTOR_3_IN_2": 21, "MOTOR_4_IN_1": 10, "MOTOR_4_IN_2": 11,
    "MOTOR_L_ENCODER_A": 30, "MOTOR_L_ENCODER_B": 31, "MOTOR_R_ENCODER_A": 24, "MOTOR_R_ENCODER_B": 25,
    "MOTOR_3_ENCODER_A": 22, "MOTOR_3_ENCODER_B": 23, "MOTOR_4_ENCODER_A": 2, "MOTOR_4_ENCODER_B": 3,
    "MOTOR_L_CURRENT": 40, "MOTOR_R_CURRENT": 43, "MOTOR_3_CURRENT": 41, "MOTOR_4_CURRENT": 42,
    "SERVO_1": 6, "SERVO_2": 9, "SERVO_3": 7, "SERVO_4": 8,
    "I2C_SDA_0": 4, "I2C_SCL_0": 5, "I2C_SDA_1": 38, "I2C_SCL_1": 39,
    "DISTANCE_TRIGGER": 0, "DISTANCE_ECHO": 1, "LINE_L": 44, "LINE_R": 45,
    "BOARD_VIN_MEASURE": 46, "BOARD_USER_BUTTON": 36, "BOARD_NEOPIXEL": 37,
    "ML_IN_1": 34, "ML_IN_2": 35, "MR_IN_1": 32, "MR_IN_2": 33, "M3_IN_1": 20, "M3_IN_2": 21,
    "M4_IN_1": 10, "M4_IN_2": 11, "ML_ENC_A": 30, "ML_ENC_B": 31, "MR_ENC_A": 24, "MR_ENC_B": 25,
    "M3_ENC_A": 22, "M3_ENC_B": 23, "M4_ENC_A": 2, "M4_ENC_B": 3,
    "ML_CUR": 40, "MR_CUR": 43, "M3_CUR": 41, "M4_CUR": 42, "S1": 6, "S2": 9, "S3": 7, "S4": 8,
    "SDA_0": 4, "SCL_0": 5, "SDA_1": 38, "SCL_1": 39, "RANGE_TRIGGER": 0, "RANGE_ECHO": 1,
    "REFLECTANCE_L": 44, "REFLECTANCE_R": 45, "BRD_VIN": 46, "BRD_USR_BTN": 36, "BRD_RGB_LED": 37,
    "NEOPIXEL": 37,
}  # fmt: skip
_POLOLU = dict(_GP30, LED=25)

_XRP_BETA.update(_XRP_LED)
_XRP.update(_XRP_LED)

BOARDS = {
    "SparkFun XRP Controller (Beta)": (30, _XRP_BETA),
    "SparkFun XRP Controller": (48, _XRP),
    "Pololu 3pi+ 2040 Robot": (30, _POLOLU),
}


def board(machine):
    """(GPIO count, board names) of the board whose name begins ``machine``, or None. (A
    board whose mpconfigboard.h sets MICROPY_BANNER_MACHINE to its name alone, as
    POLOLU_3PI_2040_ROBOT's does, has that name alone as its _machine.)"""
    for name in sorted(BOARDS, key=len, reverse=True):  # (the beta's name begins with the other's)
        if machine == name or machine.startswith(name + " with "):
            return BOARDS[name]
    return None


# Boards with a radio, and whose (network.WLAN: host/shim/network.py; socket: _hilsocket.py).
# rp2: a board whose mpconfigboard.cmake sets MICROPY_PY_NETWORK_CYW43 (ports/rp2/boards/
# <BOARD>), by its MICROPY_HW_BOARD_NAME, with its MICROPY_PY_NETWORK_HOSTNAME_DEFAULT
# (mpconfigboard.h; the port's own default, "mpy-rp2", where the board sets none). Every
# ESP32 of the loop's family has its WLAN (ports/esp32/network_wlan.c), hostname "mpy-esp32"
# (ports/esp32/mpconfigport.h). A board not named here has no radio: no network, no socket.
CYW43_BOARDS = {
    "Raspberry Pi Pico W": "PicoW",  # RPI_PICO_W
    "Raspberry Pi Pico 2 W": "Pico2W",  # RPI_PICO2_W
    "SparkFun XRP Controller (Beta)": "XRP",  # SPARKFUN_XRP_CONTROLLER_BETA (a Pico W's module)
    "SparkFun XRP Controller": "XRP",  # SPARKFUN_XRP_CONTROLLER
}


def radio(platform, machine):
    """("cyw43" or "esp32", the board's default hostname) for a board with a radio, or None."""
    if platform == "esp32":
        return ("esp32", "mpy-esp32")
    if platform == "rp2":
        for name in sorted(CYW43_BOARDS, key=len, reverse=True):
            if machine == name or machine.startswith(name + " with "):
                return ("cyw43", CYW43_BOARDS[name])
    return None
