# The pool cleaner's ADC sonar option (the design card's): each side's sounder gives a
# voltage proportional to its range, 0.33 V per metre on the board's 3.3 V ADC, a new
# value every 500 ms, 0 V when it heard nothing. No select line: both are read every
# quantum and the selected one is handed over once per 500 ms slot (the board cannot
# tell a new sample from a repeated value, so the slot runs on its own clock).
from machine import ADC, Pin

from nmea import NO_ECHO

V_PER_M = 0.33
VREF = 3.3
MIN_M = 0.05  # below this the output is the sounder's 0 V "no reading"
SLOT_MS = 500


class AnalogDepthSounders:
    def __init__(self, left_pin, right_pin):
        self._adcs = (ADC(Pin(left_pin), atten=ADC.ATTN_11DB), ADC(Pin(right_pin), atten=ADC.ATTN_11DB))
        self._u16 = [0, 0]
        self._quanta = 0
        self.selected = 0
        self.sentences = 0
        self.superseded = 0
        self.bad = 0

    def select(self, sonar):
        self.selected = sonar

    def poll(self):
        self._u16[0] = self._adcs[0].read_u16()
        self._u16[1] = self._adcs[1].read_u16()
        self._quanta += 1
        if self._quanta < SLOT_MS // 50:
            return None
        self._quanta = 0
        self.sentences += 1
        m = self._u16[self.selected] * VREF / 65535 / V_PER_M
        return NO_ECHO if m < MIN_M else m
