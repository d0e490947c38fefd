# The PIO decoder robot of the bench (docs/bench.md): both wheels of a Pico robot counted by
# a PIO quadrature decoder each, read by request every READ_MS as the SDK's
# quadrature_encoder_get_count reads it (the FIFO's old counts drained, then a fresh one),
# both wheels at full speed for RUN_MS (config.py), then stopped; it prints the reads made
# and both counts.
import time

import rp2
from config import READ_MS, RUN_MS
from decoder import quadrature
from machine import PWM, Pin


class PioEncoder:
    def __init__(self, sm_id, pin_a):
        self.sm = rp2.StateMachine(sm_id, quadrature, freq=10_000_000, in_base=Pin(pin_a))
        self.sm.active(1)

    def count(self):
        for _ in range(self.sm.rx_fifo()):
            self.sm.get()
        n = self.sm.get()
        return n - (1 << 32) if n & 0x80000000 else n


Pin(22, Pin.OUT, value=1)  # the TB6612's STBY
Pin(17, Pin.OUT, value=1)
Pin(18, Pin.OUT, value=0)
Pin(20, Pin.OUT, value=1)
Pin(19, Pin.OUT, value=0)
left, right = PioEncoder(0, 2), PioEncoder(1, 4)
motors = [PWM(Pin(16), freq=20000, duty_u16=65535), PWM(Pin(21), freq=20000, duty_u16=65535)]
reads = 0
t_stop = time.ticks_add(time.ticks_ms(), RUN_MS)
while time.ticks_diff(t_stop, time.ticks_ms()) > 0:
    time.sleep_ms(READ_MS)
    left.count()
    right.count()
    reads += 1
for motor in motors:
    motor.duty_u16(0)
time.sleep_ms(100)
print("pio_bot", reads, abs(left.count()), abs(right.count()))
