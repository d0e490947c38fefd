# The 3pi+ 2040's five down-facing QTR RC line sensors and its two bump sensors, read as
# Pololu's library reads them (pololu_3pi_2040_robot/ir_sensors.py, LineSensors and
# BumpSensors; written here, not copied). A line read: the bump
# sensors' emitters (GP23) let go, the line sensors' (GP26) driven high, the channels
# charged for 32 us (the library's PIO charges for 256 cycles at 8 MHz), let go together,
# and each timed until it reads low, up to TIMEOUT; then the emitters let go. The library
# times all seven channels (GP16..GP22, the bump sensors too) with a PIO program, a pass of
# 1 us over the pins; here the CPU charges the five line channels and polls them
# (Pin.value, ticks_us), as Pololu's QTR library for Arduino does: a fall is stamped with
# the time read before the pass that saw it. data[0] is the left sensor (GP22), data[4] the
# right (GP18); higher is darker. calibrate() and read_calibrated() are the library's
# (each channel scaled between the least of its darkest reads and the most of its lightest,
# 0 .. 1000), with a pause of 5 ms between the calibration's reads. A bump read is the
# same over the bump channels (GP17 the left, GP16 the right) with their emitters (GP23)
# lit instead; a flap is pressed above 160 % of the calibration's average reading, released
# below 140 %, as the library has it.
import time
from array import array
from machine import Pin
from micropython import const

TIMEOUT = const(1024)
_FIRST = const(16)  # QTRSensors(4, 16): GP16 .. GP22
_COUNT = const(7)


def _time_discharges(pins, data):
    """Charge the channels for 32 us, let them go together, and time each until it reads low."""
    for p in pins:
        p.init(Pin.OUT, value=1)
    time.sleep_us(32)
    n = len(pins)
    for i in range(n):
        data[i] = TIMEOUT
    for p in pins:
        p.init(Pin.IN)
    start = time.ticks_us()
    left = n
    while left:
        now = time.ticks_diff(time.ticks_us(), start)
        if now >= TIMEOUT:
            break
        for i in range(n):
            if data[i] == TIMEOUT and not pins[i].value():
                data[i] = now
                left -= 1


class LineSensors:
    def __init__(self):
        self.ir_down = Pin(26, Pin.IN)
        self.ir_bump = Pin(23, Pin.IN)
        self.pins = [Pin(_FIRST + i, Pin.IN, pull=None) for i in range(_COUNT)]
        self.line_pins = [self.pins[6 - i] for i in range(5)]  # data[i] is GP(22 - i)
        self.data = array("H", [TIMEOUT] * 5)
        self.reset_calibration()

    def reset_calibration(self):
        self.cal_min = array("H", [1025] * 5)
        self.cal_max = array("H", [0] * 5)

    def calibrate(self, reads=10):
        low = array("H", [1025] * 5)
        high = array("H", [0] * 5)
        for _ in range(reads):
            data = self.read()
            time.sleep_ms(5)
            for i in range(5):
                low[i] = min(low[i], data[i])
                high[i] = max(high[i], data[i])
        for i in range(5):
            self.cal_max[i] = max(low[i], self.cal_max[i])
            self.cal_min[i] = min(high[i], self.cal_min[i])

    def read(self):
        self.ir_bump.init(Pin.IN)
        self.ir_down.init(Pin.OUT, value=1)
        _time_discharges(self.line_pins, self.data)
        self.ir_down.init(Pin.IN)
        return self.data

    def read_calibrated(self):
        data = self.read()
        for i in range(5):
            low, high = self.cal_min[i], self.cal_max[i]
            if low >= high or data[i] < low:
                data[i] = 0
            elif data[i] > high:
                data[i] = 1000
            else:
                data[i] = (data[i] - low) * 1000 // (high - low)
        return data


class BumpSensors:
    def __init__(self):
        self.ir_down = Pin(26, Pin.IN)
        self.ir_bump = Pin(23, Pin.IN)
        self.pins = [Pin(17, Pin.IN, pull=None), Pin(16, Pin.IN, pull=None)]  # data[0] the left
        self.data = array("H", [TIMEOUT] * 2)
        self.threshold_min = array("H", [1025] * 2)  # (not calibrated: never pressed)
        self.threshold_max = array("H", [1025] * 2)
        self.pressed = [False, False]

    def calibrate(self, count=50):
        total = [0, 0]
        for _ in range(count):
            data = self.read()
            total[0] += data[0]
            total[1] += data[1]
        for i in range(2):
            self.threshold_min[i] = round(total[i] * 1.4 / count)
            self.threshold_max[i] = round(total[i] * 1.6 / count)

    def read(self):
        self.ir_down.init(Pin.IN)
        self.ir_bump.init(Pin.OUT, value=1)
        data = self.data
        _time_discharges(self.pins, data)
        self.ir_bump.init(Pin.IN)
        for i in range(2):
            self.pressed[i] = data[i] > (self.threshold_min[i] if self.pressed[i] else self.threshold_max[i])
        return data

    def left_is_pressed(self):
        return self.pressed[0]

    def right_is_pressed(self):
        return self.pressed[1]
