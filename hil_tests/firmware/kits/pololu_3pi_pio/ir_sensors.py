# ruff: noqa: F821  (a PIO body's names exist only while rp2.asm_pio assembles it; ptr16, uint: viper's)
# The 3pi+ 2040's line and bump sensors read as Pololu's library reads them, with a PIO
# program of the same shape (pololu_3pi_2040_robot/ir_sensors.py, QTRSensors, LineSensors,
# BumpSensors; written here from reading it, not copied: the library is not on PyPI, so no
# pinned copy can be fetched). One state machine of PIO1 (id 4) at 8 MHz owns GP16..GP22:
# the CPU loads OSR with ones, Y with 255 and X with the 7 pins' last state (exec'd words),
# then the program makes the 7 pins outputs (`out pindirs`, out_init high: charging), waits
# 256 cycles (32 us), takes 10 more ones into Y (the 1023 count), makes the pins inputs
# (`out pindirs` of zeros: the lines let go) and loops, 8 cycles (1 us) a pass: it samples
# the pins, and on a change pushes (autopush at 23 bits) the 7 levels and the count; at
# the count's end it pushes all ones. The CPU turns each channel's first change to low into
# TIMEOUT - count. data[0] of a line read is the left sensor (GP22), data[4] the right (GP18);
# of a bump read, data[0] the left (GP17), data[1] the right (GP16).
import rp2
from array import array
from machine import Pin
from micropython import const
from rp2 import PIO

SENSOR_COUNT = const(7)
TIMEOUT = const(1024)
_DONE = const(0)
_LINE = const(1)
_BUMP = const(2)
_state = _DONE
_shared = None


@rp2.asm_pio(
    out_init=(PIO.OUT_HIGH,) * SENSOR_COUNT,
    autopush=True,
    push_thresh=SENSOR_COUNT + 16,
    fifo_join=PIO.JOIN_RX,
)
def _discharge_timer():
    out(pindirs, SENSOR_COUNT)  # all outputs, high: the capacitors charge
    label("charging")
    jmp(y_dec, "charging")  # Y = 255 from the CPU: 256 cycles
    out(y, 10)  # the count: 1023
    mov(osr, null)
    out(pindirs, SENSOR_COUNT)  # all inputs: the lines let go
    label("sample")  # 8 cycles a pass
    in_(pins, SENSOR_COUNT)
    mov(osr, y)
    mov(y, isr)
    jmp(x_not_y, "moved")
    mov(isr, null)
    jmp("next")
    label("moved")
    mov(x, y)
    in_(osr, 16)  # levels and count: 23 bits, pushed
    label("next")
    mov(y, osr)
    jmp(y_dec, "sample")
    in_(y, 32)  # all ones: finished
    wrap_target()
    nop()
    wrap()


class QTRSensors:
    def __init__(self, id, pin1):
        for i in range(SENSOR_COUNT):
            Pin(pin1 + i, Pin.IN, pull=None)
        first = Pin(pin1, Pin.OUT, value=1)
        for i in range(1, SENSOR_COUNT):
            Pin(pin1 + i, Pin.OUT, value=1)
        self.sm = rp2.StateMachine(id, _discharge_timer, freq=8_000_000, in_base=first, out_base=first)
        self.bump = array("H", [0] * 2)
        self.line = array("H", [0] * 5)
        self.setup = array("H")
        self.setup.append(rp2.asm_pio_encode("mov(osr, invert(null))", 0))  # ones to shift out
        self.setup.append(rp2.asm_pio_encode("out(y, 8)", 0))  # 255: the charge
        self.setup.append(rp2.asm_pio_encode("out(x, 7)", 0))  # the pins were all high

    def run(self):
        self.sm.active(0)
        while self.sm.rx_fifo():
            self.sm.get()
        self.sm.restart()
        for word in self.setup:
            self.sm.exec(word)
        self.sm.active(1)

    @micropython.viper
    def _collect(self, out, first_bit: int, n: int):
        data = ptr16(out)
        for i in range(n):
            data[i] = TIMEOUT
        last = uint(0x7F0000)
        sm = self.sm
        while True:
            word = uint(sm.get())
            if word == uint(0xFFFFFFFF):
                break
            fell = last ^ word
            for i in range(n):
                if fell & (uint(1) << uint(first_bit + n - 1 - i)):
                    data[i] = TIMEOUT - word
            last = word
        return out

    def read_bump(self):
        return self._collect(self.bump, 16, 2)

    def read_line(self):
        return self._collect(self.line, 18, 5)


class _IRSensors:
    def __init__(self):
        self.ir_down = Pin(26, Pin.IN)
        self.ir_bump = Pin(23, Pin.IN)
        global _shared
        if not _shared:
            _shared = QTRSensors(4, 16)
        self.qtr = _shared
        self.reset_calibration()


class LineSensors(_IRSensors):
    def reset_calibration(self):
        self.cal_min = array("H", [1025] * 5)
        self.cal_max = array("H", [0] * 5)

    def start_read(self, emitters_on=True):
        global _state
        self.ir_bump.init(Pin.IN)
        if emitters_on:
            self.ir_down.init(Pin.OUT, value=1)
        _state = _LINE
        self.qtr.run()

    def read(self):
        global _state
        if _state != _LINE:
            self.start_read()
        data = self.qtr.read_line()
        self.ir_down.init(Pin.IN)
        self.ir_bump.init(Pin.IN)
        _state = _DONE
        return data


class BumpSensors(_IRSensors):
    def __init__(self):
        self._left = False
        self._right = False
        super().__init__()

    def reset_calibration(self):
        self.threshold_min = array("H", [1025] * 2)
        self.threshold_max = array("H", [1025] * 2)

    def calibrate(self, count=50):
        total = [0, 0]
        for _ in range(count):
            data = self.read()
            total[0] += data[0]
            total[1] += data[1]
        for i in range(2):  # pressed above 160 % of the standing average, released below 140 %
            self.threshold_min[i] = round(total[i] * 1.4 / count)
            self.threshold_max[i] = round(total[i] * 1.6 / count)

    def start_read(self, emitters_on=True):
        global _state
        self.ir_down.init(Pin.IN)
        if emitters_on:
            self.ir_bump.init(Pin.OUT, value=1)
        _state = _BUMP
        self.qtr.run()

    def read(self):
        global _state
        if _state != _BUMP:
            self.start_read()
        data = self.qtr.read_bump()
        self.ir_down.init(Pin.IN)
        self.ir_bump.init(Pin.IN)
        _state = _DONE
        self._left = data[0] > (self.threshold_min[0] if self._left else self.threshold_max[0])
        self._right = data[1] > (self.threshold_min[1] if self._right else self.threshold_max[1])
        return data

    def left_is_pressed(self):
        return self._left

    def right_is_pressed(self):
        return self._right
