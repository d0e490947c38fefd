# dht_readinto(pin, buf): a DHT11 / DHT22 read (MicroPython's drivers/dht/dht.c, which the
# ESP32 port gives as esp.dht_readinto and the RP2 port as rp2.dht_readinto), at the
# frame level: the start as the C code makes it on the pin (open drain: high 250 ms, low
# 18 ms, let go), then the sensor's 40 bits as one read of 5 bytes on the pin's line
# "dht:<pin>" (a BUS frame the host answers from the dht part on that line:
# sim_plant/catalogue/dht.py); the clock moves on by the reply's length as its bits make it.
# No sensor on the line: OSError(ETIMEDOUT) 100 us after the release, as the C code's wait.
import time

import _hil
import _hilframe as F
from _hilbuf import wbuf
from _hilbus import ETIMEDOUT, _Bus, _key

ADDRESS = 0x40  # (the one device on a line answers here: sim_plant/catalogue/dht.py)
RELEASE_US = 10  # the C code's wait after letting the line go
WAKE_US = 30  # the sensor pulls the line low 20-40 us after the release
PREAMBLE_US = 160  # its 80 us low, 80 us high
BIT_LOW_US, ZERO_US, ONE_US = 50, 26, 70


class _Line(_Bus):
    def __init__(self, pin):
        self._open(F.CFG_I2C, "dht:" + _key(pin), 1)


def _reply_us(data):
    ones = sum(bin(b).count("1") for b in data)
    return WAKE_US + PREAMBLE_US + 40 * BIT_LOW_US + ones * ONE_US + (40 - ones) * ZERO_US + BIT_LOW_US


def dht_readinto(pin, buf):
    view = buf if type(buf) is bytearray else wbuf(buf)  # (drivers/dht/dht.c: MP_BUFFER_WRITE, in bytes)
    if len(view) < 5:
        raise ValueError("buffer too small")
    pin.init(pin.OPEN_DRAIN)
    pin.value(1)
    time.sleep_ms(250)
    pin.value(0)
    time.sleep_ms(18)
    pin.value(1)
    line = _Line(pin)
    status, _count, got, t = _hil.transfer(line._handle, F.BUS_XFER, ADDRESS, 5, b"")
    if status != F.BUS_OK or len(got) < 5:
        _hil.bus_time(t + RELEASE_US + 100)
        raise OSError(ETIMEDOUT)
    _hil.bus_time(t + RELEASE_US + _reply_us(got))
    view[:5] = got[:5]
