# kitbot: the board support of a small two-wheel robot on an RP2040, written as robot kits'
# MicroPython libraries are (one module per device, relative imports between them, the
# hardware reached through machine, rp2 and mem32 as the kit's own code reaches it).
# The pins, by function:
#   I2C0 GP4 (SDA), GP5 (SCL): an LSM6DSO IMU at 0x6B and an LIS3MDL compass at 0x1E
#   GP10, GP11: right and left motor direction; GP14, GP15: their PWM (slice 7, A and B)
#   GP8/GP9, GP12/GP13: right and left encoder A/B (counted by PIO0 state machines 1, 0)
#   SPI0 GP2 (SCK), GP3 (MOSI), GP0 (D/C), GP1 (RES): an SH1106 display, CS tied low
#   SPI0 GP6 (SCK), GP3 (MOSI): a chain of APA102 RGB LEDs (the SPI's clock on GP2 or GP6 by
#   which of them is in the SPI function, Pin.ALT, the other a GPIO output)
#   GP16, GP17, GP18: three QTR-RC line sensor channels; GP19: their IR emitters
#   GP20: button A (to ground); BOOTSEL: the board's boot button
from .buttons import ButtonA, bootsel_pressed
from .display import Display
from .encoders import Encoders
from .imu import IMU
from .line_sensors import LineSensors
from .motors import Motors
from .rgb_leds import RGBLEDs

__all__ = ["Motors", "Encoders", "IMU", "Display", "LineSensors", "RGBLEDs", "ButtonA", "bootsel_pressed"]
