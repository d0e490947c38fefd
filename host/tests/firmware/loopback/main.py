# Board outputs wired to board inputs (the bench of host/conformance: GPIO4 to GPIO5,
# GPIO12 to GPIO13, as upstream's esp32 target wiring), driven the way upstream's
# hardware tests drive them: a write read back at once, a PWM timed with time_pulse_us,
# quadrature steps counted by Encoder units, pulses by Counter units.
import time
from machine import PWM, Counter, Encoder, Pin, time_pulse_us

out0 = Pin(4, Pin.OUT, value=0)
in0 = Pin(5, Pin.IN)
out1 = Pin(12, Pin.OUT, value=0)
in1 = Pin(13, Pin.IN)

# A write is seen by the wired input at the same instant.
seen = []
t0 = time.ticks_us()
for level in (1, 0, 1, 0):
    out0(level)
    seen.append(in0())
print("R readback", seen)
print("R readback_us", time.ticks_diff(time.ticks_us(), t0))

# A PWM's low and high phases, timed on the wired input (upstream's machine_pwm way).
pwm_err = []
pwm = PWM(Pin(4), freq=1000, duty_u16=0)
for freq, duty in ((50, 25), (1000, 10), (1000, 50), (5000, 90), (20000, 75)):
    pwm.init(freq=freq, duty_u16=duty * 65535 // 100)
    total = 1_000_000 // freq
    expect = (total - total * (duty * 65535 // 100) // 65535, total * (duty * 65535 // 100) // 65535)
    for level in (0, 1):
        time_pulse_us(in0, level, 2 * total)  # settle
        got = time_pulse_us(in0, level, 2 * total)
        pwm_err.append(abs(got - expect[level]))
pwm.duty_u16(0)
print("R pwm_err", pwm_err)
print("R pwm_held_low", [time_pulse_us(in0, 1, 5000), in0()])
pwm.deinit()
out0 = Pin(4, Pin.OUT, value=1)
out1(1)

# Encoder units in 1, 2 and 4 phases on the two wires (upstream's test_partial steps),
# on the pins the bench's target_wiring names, as upstream's machine_encoder.py takes them.
from target_wiring import encoder_loopback_id, encoder_loopback_in_pins  # noqa: E402

enc = [Encoder(encoder_loopback_id + i, *encoder_loopback_in_pins, phases=n) for i, n in ((0, 1), (1, 2), (2, 4))]
pulses = 0


def rotate(n):
    global pulses
    for _ in range(abs(n)):
        pulses += 1 if n > 0 else -1
        if (pulses % 2) == (1 if n > 0 else 0):
            out0(not out0())
        else:
            out1(not out1())


positions = []
for n in (1, 1, 1, 1, 1, 1, 1, 1, -1, -3, -4, -1, -1, -1, -1, -1, -3, 100, -100):
    rotate(n)
    positions.append(tuple(e.value() for e in enc))
print("R encoder", positions)
for e in enc:
    e.deinit()

# Counter units: rising edges up, then down after init; falling edges; a burst of 300.
out0(0)
cnt = Counter(0, in0)
for _ in range(100):
    out0(1)
    out0(0)
up = cnt.value()
out0(1)
at_101 = cnt.value(0)
after_reset = cnt.value()
cnt.init(in0, direction=Counter.DOWN)
cnt.value(100)
for _ in range(25):
    out0(0)
    out0(1)
down = cnt.value()
cnt.init(in0, edge=Counter.FALLING)
for _ in range(300):
    out0(0)
    out0(1)
print("R counter", [up, at_101, after_reset, down, cnt.value()])
cnt.deinit()
out0(0)
out0(1)
print("R after_deinit", cnt.value())

# A UART's TX wired to its RX: bytes take their time at the baud rate, IRQ_RX per byte.
from machine import UART  # noqa: E402

got = []
uart = UART(1, 9600)
uart.irq(lambda u: got.append((time.ticks_us(), u.read(1))), UART.IRQ_RX)
t0 = time.ticks_us()
uart.write("abc")
uart.flush()
flushed = time.ticks_diff(time.ticks_us(), t0)
time.sleep_ms(10)
print("R uart", [flushed, [(time.ticks_diff(t, t0), b) for t, b in got]])
