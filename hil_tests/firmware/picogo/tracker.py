# The line sensor board's TLC1543 read two ways, in the style of the Pico-Go's published
# demos (written here, not copied): a PIO program that side-sets the I/O clock, shifts the
# next channel's address out and the last conversion in, 12 clocks at 200 kHz, with the
# CPU's chip select around each put and get; and the CPU toggling the pins itself, as the
# first boards' code and the AlphaBot2's do. Each cycle returns the conversion the cycle
# before addressed, so channel n's value comes with the cycle that asks for n + 1.
import rp2
import time
from machine import Pin


@rp2.asm_pio(
    out_shiftdir=0,
    autopull=True,
    pull_thresh=12,
    autopush=True,
    push_thresh=12,
    sideset_init=(rp2.PIO.OUT_LOW),
    out_init=rp2.PIO.OUT_LOW,
)
def adc_cycle():
    out(pins, 1).side(0)[1]  # noqa: F821 (the address bit, the clock low)
    in_(pins, 1).side(1)[1]  # noqa: F821 (the data bit, the clock high)


class Tracker:
    def __init__(self, count=5):
        self.count = count
        self.cs = Pin(28, Pin.OUT)
        self.cs.value(1)
        self.sm = rp2.StateMachine(
            1, adc_cycle, freq=800_000, sideset_base=Pin(6, Pin.OUT), out_base=Pin(7, Pin.OUT), in_base=Pin(27, Pin.IN)
        )
        self.sm.active(1)

    def read(self):
        vals = [0] * (self.count + 1)
        for ch in range(self.count + 1):
            self.cs.value(0)
            self.sm.put(ch << 28)
            vals[ch] = (self.sm.get() & 0xFFF) >> 2
            self.cs.value(1)
        time.sleep_ms(2)
        return vals[1:]


class BitBanged:
    def __init__(self, count=5):
        self.count = count
        self.cs = Pin(28, Pin.OUT)
        self.clk = Pin(6, Pin.OUT)
        self.addr = Pin(7, Pin.OUT)
        self.dout = Pin(27, Pin.IN, Pin.PULL_UP)
        self.cs.value(1)
        self.clk.value(0)

    def read(self):
        vals = [0] * (self.count + 1)
        for ch in range(self.count + 1):
            self.cs.value(0)
            for i in range(10):
                if i < 4:
                    self.addr.value((ch >> (3 - i)) & 1)
                vals[ch] = (vals[ch] << 1) | self.dout.value()
                self.clk.value(1)
                self.clk.value(0)
            time.sleep_us(30)
            self.cs.value(1)
        return vals[1:]
