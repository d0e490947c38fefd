# The motor controller of a two-board rover, on a Raspberry Pi Pico: two TB6612FNG
# channels, N20 motors with Hall quadrature encoders. The navigation board sends wheel
# speed targets on UART0 ("V <left> <right>\n", encoder counts a second); a speed loop
# every 20 ms holds them and answers with the encoder counts ("O <left> <right>\n").
# With no command for 500 ms it stops the motors: the navigator is gone.
import time

from machine import PWM, UART, Pin

PWMA, AIN1, AIN2 = 16, 17, 18
PWMB, BIN1, BIN2 = 21, 20, 19
STBY = 22
ENC_LA, ENC_LB = 2, 3
ENC_RA, ENC_RB = 4, 5
LINK_UART = 0  # TX GP0, RX GP1
LED = 25

LOOP_MS = 20
KI = 0.0001  # duty per (count/s of error) per loop
KF = 0.00085  # feed-forward: duty per count/s
SILENCE_MS = 500


class Motor:
    """One TB6612FNG channel: two direction pins and a PWM."""

    def __init__(self, pwm, in1, in2):
        self.pwm = PWM(Pin(pwm))
        self.pwm.freq(20000)
        self.in1 = Pin(in1, Pin.OUT)
        self.in2 = Pin(in2, Pin.OUT)

    def drive(self, s):  # -1..1
        self.in1.value(1 if s > 0 else 0)
        self.in2.value(1 if s < 0 else 0)
        self.pwm.duty_u16(int(min(abs(s), 1.0) * 65535))


class Encoder:
    """Quadrature encoder counted on both edges of channel A (B gives the direction)."""

    def __init__(self, pin_a, pin_b):
        self.a = Pin(pin_a, Pin.IN)
        self.b = Pin(pin_b, Pin.IN)
        self.count = 0
        self.a.irq(trigger=Pin.IRQ_RISING | Pin.IRQ_FALLING, handler=self._edge, hard=True)

    def _edge(self, pin):
        if self.a.value() == self.b.value():
            self.count -= 1
        else:
            self.count += 1


class Wheel:
    """A motor and its encoder, held at a speed (counts a second) by a PI loop."""

    def __init__(self, motor, encoder):
        self.motor, self.encoder = motor, encoder
        self.target = 0
        self.trim = 0.0
        self.last = 0

    def hold(self, target):
        if (target > 0) != (self.target > 0) or target == 0:
            self.trim = 0.0  # (the other way round: what it learnt does not hold)
        self.target = target

    def step(self, dt_ms):
        count = self.encoder.count
        speed = (count - self.last) * 1000 // dt_ms
        self.last = count
        if self.target == 0:
            self.trim = 0.0
            self.motor.drive(0)
            return
        self.trim += KI * (self.target - speed)
        self.motor.drive(KF * self.target + self.trim)


left = Wheel(Motor(PWMA, AIN1, AIN2), Encoder(ENC_LA, ENC_LB))
right = Wheel(Motor(PWMB, BIN1, BIN2), Encoder(ENC_RA, ENC_RB))
stby = Pin(STBY, Pin.OUT, value=1)
led = Pin(LED, Pin.OUT)
link = UART(LINK_UART, baudrate=115200)
print("motor: ready")


def command(line, now):
    parts = line.split()
    if len(parts) == 3 and parts[0] == b"V":
        left.hold(int(parts[1]))
        right.hold(int(parts[2]))
        return now
    print("motor: bad command", line)
    return None


buf = b""
heard = time.ticks_ms()
stopped = True
t_next = time.ticks_ms()
while True:
    t_next = time.ticks_add(t_next, LOOP_MS)
    led.toggle()
    now = time.ticks_ms()
    if link.any():
        buf += link.read()
        while b"\n" in buf:
            line, buf = buf.split(b"\n", 1)
            heard = command(line, now) or heard
            link.write(b"O %d %d\n" % (left.encoder.count, right.encoder.count))
    if time.ticks_diff(now, heard) > SILENCE_MS:
        if not stopped:
            print("motor: no command for %d ms, stopping" % SILENCE_MS)
        left.hold(0)
        right.hold(0)
        stopped = True
    elif left.target or right.target:
        stopped = False
    left.step(LOOP_MS)
    right.step(LOOP_MS)
    time.sleep_ms(max(0, time.ticks_diff(t_next, time.ticks_ms())))
