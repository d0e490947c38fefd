# A kit's habit (a display's SPI clock shared with a GPIO): GP10 is used as a plain output,
# then handed back to SPI1 with Pin.ALT before each transfer, as the kit's display driver
# does; while in ALT, Pin.value(x) reaches only SIO's latch. GP2 is wired to GP3.
import time
from machine import SPI, Pin

cs = Pin(9, Pin.OUT, value=1)
spi = SPI(1, baudrate=1_000_000, sck=Pin(10), mosi=Pin(11), miso=Pin(12))
sck = Pin(10, Pin.OUT, value=1)  # borrowed as a GPIO
sck.init(mode=Pin.ALT, alt=Pin.ALT_SPI)  # and handed back to the SPI block
print("R repr", repr(repr(sck)))
cs(0)
spi.write(b"\x8f")
who = spi.read(1)
cs(1)
print("R who", list(who))

out = Pin(2, Pin.OUT, value=1)
seen = Pin(3, Pin.IN)
levels = [seen()]
out.init(mode=Pin.ALT, alt=Pin.ALT_PWM)  # the PWM block's now: SIO drives it no more
out.value(0)  # the latch only
time.sleep_ms(1)
levels.append(seen())  # (the wire: still what SIO drove last)
out.init(mode=Pin.OUT)  # SIO's again: the latch's 0 reaches the pad
time.sleep_ms(1)
levels.append(seen())
print("R levels", levels)
