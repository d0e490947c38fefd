# The SPI API against the bench's LSM6DSOX on spi1, its chip select a Pin the firmware drives.
import time
from machine import SPI, Pin, SoftSPI

soft = SoftSPI(baudrate=100_000, sck=Pin(5), mosi=Pin(4), miso=Pin(2))  # its own bus, nobody on it
print("R soft", list(soft.read(1)))

cs = Pin(15, Pin.OUT, value=1)
spi = SPI(1, baudrate=1_000_000, polarity=0, phase=0, sck=Pin(14), mosi=Pin(13), miso=Pin(12))
print("R unselected", list(spi.read(2, 0x8F)))
cs(0)
t0 = time.ticks_us()
spi.write(b"\x8f")
who = spi.read(1)
print("R spi_us", time.ticks_diff(time.ticks_us(), t0))
cs(1)
print("R who", list(who))
cs(0)
spi.write(b"\x11\x40")  # CTRL2_G
cs(1)
cs(0)
buf = bytearray(3)
spi.write_readinto(b"\x90\x00\x00", buf)  # read CTRL1_XL, CTRL2_G
cs(1)
print("R ctrl", list(buf))
cs(0)
spi.write(b"\x8f")
one = bytearray(1)
spi.readinto(one)
cs(1)
print("R readinto", list(one))
try:
    spi.write_readinto(b"\x00", bytearray(2))
except ValueError:
    print("R lengths", "'ValueError'")
try:
    SPI(0)
except ValueError as e:
    print("R bad_id", repr(str(e)))
lsb = SPI(1, baudrate=100_000, firstbit=SPI.LSB, sck=Pin(14), mosi=Pin(13), miso=Pin(12))
cs(0)
lsb.write(bytes((0xF1,)))  # 0x8F sent LSB first
print("R lsb_who", list(lsb.read(1)))  # the chip sends 0x6C MSB first
cs(1)
