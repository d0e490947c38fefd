# _onewire: the 1-Wire primitives MicroPython's ports build in (extmod/modonewire.c: reset,
# readbit, readbyte, writebit, writebyte, crc8), against the plant's part on the pin's line
# "onewire:<pin>" (a ds18b20: sim_plant/catalogue/ds18b20.py). Each primitive is one BUS
# frame the host answers from that part as the plant is at the slot's instant, the
# operation's byte first (RESET .. READ_BYTE below); then the clock moves on by the slots'
# time as the C's TIMING_* make them: a reset 480 + 70 + 410 us, a bit 70 us (6 + 9 + 55 to
# read, 6 + 54 + 10 to write), a byte 8 bits. With no part on the line nobody answers: a
# reset finds no presence (False), read slots read the line's pull-up (1s), as on a board.
import _hil
import _hilframe as F
from _hilbuf import rbuf
from _hilbus import _Bus, _key

ADDRESS = 0x40  # (the one device on a line answers here: sim_plant/catalogue/ds18b20.py)
RESET, WRITE_BIT, WRITE_BYTE, READ_BIT, READ_BYTE = 0, 1, 2, 3, 4
RESET_US = 480 + 70 + 410  # TIMING_RESET1..3
BIT_US = 70  # TIMING_READ1..3, TIMING_WRITE1..3


class _Line(_Bus):
    def __init__(self, key):
        self._open(F.CFG_I2C, "onewire:" + key, 1)


_lines = {}


def _line(pin):
    key = _key(pin)
    line = _lines.get(key)
    if line is None:
        line = _lines[key] = _Line(key)
    return line


def _slot(pin, op, value, n_read, slot_us):
    line = _line(pin)
    data = bytes((op, value & 0xFF)) if n_read == 0 else bytes((op,))
    status, _count, got, t = _hil.transfer(line._handle, F.BUS_XFER, ADDRESS, n_read, data)
    _hil.bus_time(t + slot_us)
    if status != F.BUS_OK or len(got) < n_read:
        return None  # (nobody on the line)
    return got[0] if n_read else 0


def needs(pin):
    """What a line with no part needs, in words (the shim's onewire puts it in OneWireError)."""
    key = _key(pin)
    return (
        "no 1-Wire device answered on pin %s: the line onewire:%s needs a ds18b20 part wired to that pin "
        '(in the rig file: [[plant.parts]] kind = "ds18b20", bus = "onewire:%s"; docs/parts.md)' % (key, key, key)
    )


def reset(pin):
    return _slot(pin, RESET, 0, 1, RESET_US) is not None  # (onewire_bus_reset: the presence pulse)


def readbit(pin):
    got = _slot(pin, READ_BIT, 0, 1, BIT_US)
    return 1 if got is None else got & 1


def readbyte(pin):
    got = _slot(pin, READ_BYTE, 0, 1, 8 * BIT_US)
    return 0xFF if got is None else got


def writebit(pin, value):
    _slot(pin, WRITE_BIT, 1 if value else 0, 0, BIT_US)


def writebyte(pin, value):
    _slot(pin, WRITE_BYTE, value, 0, 8 * BIT_US)


def crc8(data):
    # (onewire_crc8: the Dallas CRC, polynomial 0x8C reflected, over a read buffer)
    crc = 0
    for byte in rbuf(data):
        for _ in range(8):
            mix = (crc ^ byte) & 1
            crc >>= 1
            if mix:
                crc ^= 0x8C
            byte >>= 1
    return crc
