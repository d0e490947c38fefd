# The duct robot's board code: a hardware timer at 160 Hz (the base tick); every 8 ticks
# (50 ms) the speed loops run on the slot counts the encoder IRQs made (zeroed after each
# read), the three sonars are sampled with the speeds and the record goes into the ring.
# The main loop reads the sonars every 10 ms for the navigation (fast reaction to
# branches and ends) and serves the master on the UART.
import micropython
from machine import ADC, PWM, UART, Pin, Timer, disable_irq, enable_irq
from micropython import const
from time import sleep_ms

import board
from duct_link import RecordRing, format_batch, parse_command
from duct_nav import DONE, Explorer
from duct_odometry import Odometry
from duct_sonar import GAINS100, SonarFilter
from duct_speed import DUTY_TOP, WheelLoop

BASE_HZ = const(160)  # 6.25 ms base tick
TICKS_PER_LOOP = const(8)  # "every 8 timer interrupts the speed control algorithm"
MAIN_MS = const(10)
BAUD = const(115200)
PWM_HZ = const(20000)


class SlotCounter:
    def __init__(self, pin_id):
        self.n = 0
        self.total = 0
        self.pin = Pin(pin_id, Pin.IN)
        self.pin.irq(self._slot, Pin.IRQ_RISING)

    def _slot(self, _pin):
        self.n += 1

    def take(self):
        state = disable_irq()
        n, self.n = self.n, 0
        enable_irq(state)
        self.total += n
        return n


class Motor:
    """LMD18200: DIR and the PWM magnitude."""

    def __init__(self, dir_id, pwm_id):
        self.dir = Pin(dir_id, Pin.OUT, value=1)
        self.pwm = PWM(Pin(pwm_id), freq=PWM_HZ, duty_u16=0)

    def drive(self, duty):
        self.dir.value(1 if duty >= 0 else 0)
        self.pwm.duty_u16((duty if duty >= 0 else -duty) * 65535 // DUTY_TOP)


class DuctRobot:
    def __init__(self):
        self.motors = (Motor(board.MOTOR_L_DIR, board.MOTOR_L_PWM), Motor(board.MOTOR_R_DIR, board.MOTOR_R_PWM))
        self.slots = (SlotCounter(board.ENC_L), SlotCounter(board.ENC_R))
        self.loops = (WheelLoop(), WheelLoop())
        self.adcs = (ADC(Pin(board.SONAR_F_ADC)), ADC(Pin(board.SONAR_L_ADC)), ADC(Pin(board.SONAR_R_ADC)))
        self.filters = tuple(SonarFilter(g) for g in GAINS100)
        self.ring = RecordRing()
        self.odo = Odometry()
        self.nav = Explorer(self.odo, self.log)
        self.uart = UART(board.LINK_UART, BAUD)
        self.probe = Pin(board.LOOP_PROBE, Pin.OUT, value=0)
        self.mode = "auto"
        self.ticks = 0
        self.loops_run = 0
        self.line = b""
        self.timer = Timer(0)

    def log(self, what, odo, *point):
        extra = (" at (%.0f, %.0f) mm" % point) if point else ""
        print(
            "%s at %d ms: x %.0f mm y %.0f mm theta %.1f deg%s"
            % (what, self.loops_run * 50, odo.x_mm, odo.y_mm, odo.theta * 57.29578, extra)
        )

    def sonar_raw(self):
        return tuple(a.read_u16() >> 8 for a in self.adcs)

    def _tick(self, _timer):
        self.ticks += 1
        if self.ticks % TICKS_PER_LOOP == 0:
            self.control()

    def control(self):
        """The speed control interrupt's work (App. D.4, §3.5.2)."""
        self.probe.toggle()
        self.loops_run += 1
        counts = (self.slots[0].take(), self.slots[1].take())
        signed = [counts[0] * self.loops[0].sign, counts[1] * self.loops[1].sign]
        duties = [self.loops[0].update(counts[0]), self.loops[1].update(counts[1])]
        sl, sr = self.loops[0].set_ticks, self.loops[1].set_ticks
        if sl and sl == -sr:  # a spin: the backward wheel's encoder slips (§5.7), so it
            fwd = 0 if sl > 0 else 1  # takes the forward wheel's duty, not its own loop's
            duties[1 - fwd] = -duties[fwd]
            self.loops[1 - fwd].duty = self.loops[fwd].duty
        self.motors[0].drive(duties[0])
        self.motors[1].drive(duties[1])
        self.odo.update(signed[0], signed[1])
        f, left, right = self.sonar_raw()
        self.ring.push(counts[0], counts[1], f, left, right)

    def set_speeds(self, left, right):
        if left != self.loops[0].set_ticks:
            self.loops[0].set(left)
        if right != self.loops[1].set_ticks:
            self.loops[1].set(right)

    def command(self, cmd):
        op = cmd[0]
        if op == "R":
            self.uart.write(format_batch(self.ring.drain(), self.ring.overruns))
        elif op == "E":
            self.mode = "estop"
            self.set_speeds(0, 0)
            print("e-stop at %d ms" % (self.loops_run * 50))
        elif op == "A":
            self.mode = "auto"
        elif op == "S":
            self.mode = "manual"
            self.set_speeds(cmd[1], cmd[2])
        elif op == "K":
            for loop in self.loops:
                loop.kp100 = cmd[1]
        elif op == "O":
            self.nav.override, self.nav.fix = bool(cmd[1]), bool(cmd[2])

    def serve(self):
        while self.uart.any():
            self.line += self.uart.read()
            while b"\n" in self.line:
                raw, self.line = self.line.split(b"\n", 1)
                cmd = parse_command(raw.decode())
                if cmd:
                    self.command(cmd)

    def step(self):
        self.serve()
        raw = self.sonar_raw()
        f, left, right = (flt.push(v) for flt, v in zip(self.filters, raw))
        if self.mode != "auto" or self.nav.state == DONE:
            return
        total = (self.slots[0].total + self.slots[0].n, self.slots[1].total + self.slots[1].n)
        self.set_speeds(*self.nav.step(f, left, right, total[0], total[1]))
        if self.nav.state == DONE:
            n = self.nav
            print("explored: %d branches found, %d ends, %d left in the list" % (n.found, n.ends, len(n.branches)))

    def run(self):
        if hasattr(micropython, "alloc_emergency_exception_buf"):
            micropython.alloc_emergency_exception_buf(100)
        print("duct robot on", board.NAME + ": speed loop every", TICKS_PER_LOOP, "ticks of", BASE_HZ, "Hz")
        self.timer.init(freq=BASE_HZ, mode=Timer.PERIODIC, callback=self._tick)
        while True:
            self.step()
            sleep_ms(MAIN_MS)


def run():
    DuctRobot().run()
