# The controller's user button (to ground, pulled up) and, on the RP2350 controller, its
# RGB LED (one NeoPixel).
import time
from machine import Pin


class Board:
    def __init__(self, button, rgb_pin=None):
        self.button = Pin(button, Pin.IN, Pin.PULL_UP)
        self.rgb = None
        if rgb_pin is not None:
            from neopixel import NeoPixel

            self.rgb = NeoPixel(Pin(rgb_pin, Pin.OUT), 1)

    def is_button_pressed(self):
        return self.button.value() == 0

    def wait_for_button(self):
        while not self.is_button_pressed():
            time.sleep_ms(10)
        while self.is_button_pressed():
            time.sleep_ms(10)

    def set_rgb(self, colour):
        if self.rgb is not None:
            self.rgb[0] = colour
            self.rgb.write()
