# Seed 002's duct robot as it was built (§3.4, §3.5; docs/duct.md, "As built"): this is its
# low-level MCU (the "Roboaudiostix", an ATmega128 on the robot; here the firmware of an
# RP2040 with the one-board robot's pins, rpi_pico_duct), an I2C target of the Linux master
# (the Gumstix: a host program, hil_tests/duct_as_built/gumstix.py; the two-board rig file
# is as_built.toml beside this file). A 160 Hz timer, the speed loops every 8 ticks on the
# slot counts the encoder IRQs make, the three sonars read and filtered every 10 ms, the
# speed records in a ring: all of it a register file at 0x0b (the Robostix's I2C address).
#
# Registers: 0..3 and 4..7 the left and right slot totals (u32), 8..10 the filtered front,
# left and right sonar readings, 11 the records in the mailbox; 16..19 the set speeds (two
# i16, ticks a period), 20 the command flags (bit 0: take the records into the mailbox at
# 32..63, up to 8, each two i16: a period's signed slot counts; more are lost, as the seed's
# master had to poll "more frequently than the data is added"; bit 1: emergency stop). A
# write to 16.. is acted on when it ends (its IRQ_END_WRITE handler).
import struct
from machine import ADC, PWM, I2CTarget, Pin, Timer, disable_irq, enable_irq
from micropython import const
from time import sleep_ms

import board
from duct_link import RecordRing
from duct_sonar import GAINS100, SonarFilter
from duct_speed import DUTY_TOP, WheelLoop

ADDR = const(0x0B)
BASE_HZ = const(160)
TICKS_PER_LOOP = const(8)
MAIN_MS = const(10)
PWM_HZ = const(20000)
MAILBOX = const(32)
TAKE, ESTOP = 1, 2


class Robostix:
    def __init__(self):
        # each LMD18200's DIR and PWM; each wheel's slot interrupter, its edges counted by an IRQ
        self.dirs = (Pin(board.MOTOR_L_DIR, Pin.OUT, value=1), Pin(board.MOTOR_R_DIR, Pin.OUT, value=1))
        self.pwms = tuple(PWM(Pin(p), freq=PWM_HZ, duty_u16=0) for p in (board.MOTOR_L_PWM, board.MOTOR_R_PWM))
        self.counts = [0, 0]  # slots since the last speed loop
        self.totals = [0, 0]
        self.enc = (Pin(board.ENC_L, Pin.IN), Pin(board.ENC_R, Pin.IN))
        self.enc[0].irq(self._left, Pin.IRQ_RISING)
        self.enc[1].irq(self._right, Pin.IRQ_RISING)
        self.loops = (WheelLoop(), WheelLoop())
        self.adcs = (ADC(Pin(board.SONAR_F_ADC)), ADC(Pin(board.SONAR_L_ADC)), ADC(Pin(board.SONAR_R_ADC)))
        self.filters = tuple(SonarFilter(g) for g in GAINS100)
        self.ring = RecordRing()
        self.probe = Pin(board.LOOP_PROBE, Pin.OUT, value=0)
        self.regs = bytearray(64)
        self.ticks = 0
        self.stopped = False
        self.target = I2CTarget(0, ADDR, mem=self.regs)
        self.target.irq(self._written, trigger=I2CTarget.IRQ_END_WRITE)
        self.timer = Timer(0)

    def _left(self, _pin):
        self.counts[0] += 1

    def _right(self, _pin):
        self.counts[1] += 1

    def _take(self):
        """The slots counted since the last speed loop (zeroed), added to the totals."""
        state = disable_irq()
        counts, self.counts = self.counts, [0, 0]
        enable_irq(state)
        self.totals[0] += counts[0]
        self.totals[1] += counts[1]
        return counts

    def _drive(self, side, duty):
        self.dirs[side].value(1 if duty >= 0 else 0)
        self.pwms[side].duty_u16(abs(duty) * 65535 // DUTY_TOP)

    def _tick(self, _timer):
        self.ticks += 1
        if self.ticks % TICKS_PER_LOOP == 0:
            self.control()

    def control(self):
        self.probe.toggle()
        counts = self._take()
        duties = [self.loops[0].update(counts[0]), self.loops[1].update(counts[1])]
        sl, sr = self.loops[0].set_ticks, self.loops[1].set_ticks
        if sl and sl == -sr:  # a spin: the backward wheel takes the forward wheel's duty (§5.7)
            fwd = 0 if sl > 0 else 1
            duties[1 - fwd] = -duties[fwd]
            self.loops[1 - fwd].duty = self.loops[fwd].duty
        self._drive(0, duties[0])
        self._drive(1, duties[1])
        raw = self.sonar_raw()
        self.ring.push(counts[0] * self.loops[0].sign, counts[1] * self.loops[1].sign, *raw)

    def sonar_raw(self):
        return tuple(a.read_u16() >> 8 for a in self.adcs)

    def _written(self, target):
        if target.memaddr != 16:
            return
        left, right, flags = struct.unpack_from("<hhB", self.regs, 16)
        if flags & ESTOP and not self.stopped:
            self.stopped = True
            print("e-stop at %d ms" % (self.ticks * 1000 // BASE_HZ))
        if self.stopped:
            left = right = 0
        for loop, ticks in zip(self.loops, (left, right)):
            if ticks != loop.set_ticks:
                loop.set(ticks)
        if flags & TAKE:
            records = self.ring.drain()[:8]
            for i, record in enumerate(records):
                struct.pack_into("<hh", self.regs, MAILBOX + 4 * i, record[1], record[2])
            self.regs[11] = len(records)

    def step(self):
        raw = self.sonar_raw()
        f, left, right = (flt.push(v) for flt, v in zip(self.filters, raw))
        state = disable_irq()
        totals = (self.totals[0] + self.counts[0], self.totals[1] + self.counts[1])
        enable_irq(state)
        struct.pack_into("<IIBBB", self.regs, 0, totals[0], totals[1], f, left, right)

    def run(self):
        print("robostix on", board.NAME + ": I2C target at 0x%02x, speed loop every" % ADDR, TICKS_PER_LOOP, "ticks")
        self.timer.init(freq=BASE_HZ, mode=Timer.PERIODIC, callback=self._tick)
        while True:
            self.step()
            sleep_ms(MAIN_MS)


Robostix().run()
