# The reflectance board's two channels on the ADC: 0.0 white to 1.0 black.
from machine import ADC, Pin


class Reflectance:
    def __init__(self, left="LINE_L", right="LINE_R"):
        self.left = ADC(Pin(left))
        self.right = ADC(Pin(right))

    def get_left(self):
        return self.left.read_u16() / 65535

    def get_right(self):
        return self.right.read_u16() / 65535
