# onewire: the 1-Wire bus driver the ESP32, ESP8266 and RP2 ports freeze (micropython-lib's
# micropython/drivers/bus/onewire), with its API: OneWire(pin) with reset(required),
# readbit, readbyte, readinto, write, writebit, writebyte, select_rom, scan, crc8, and
# OneWireError. The loop's build freezes no micropython-lib module, so the shim has its own,
# on the port's _onewire primitives (host/shim/_onewire.py); docs/shim.md, "1-Wire".
import _onewire

SEARCH_ROM = 0xF0
MATCH_ROM = 0x55
SKIP_ROM = 0xCC


class OneWireError(Exception):
    pass


class OneWire:
    SEARCH_ROM = SEARCH_ROM
    MATCH_ROM = MATCH_ROM
    SKIP_ROM = SKIP_ROM

    def __init__(self, pin):
        self.pin = pin
        self.pin.init(pin.OPEN_DRAIN, pin.PULL_UP)

    def reset(self, required=False):
        present = _onewire.reset(self.pin)
        if required and not present:
            raise OneWireError(_onewire.needs(self.pin))
        return present

    def readbit(self):
        return _onewire.readbit(self.pin)

    def readbyte(self):
        return _onewire.readbyte(self.pin)

    def readinto(self, buf):
        for i in range(len(buf)):
            buf[i] = _onewire.readbyte(self.pin)

    def writebit(self, value):
        return _onewire.writebit(self.pin, value)

    def writebyte(self, value):
        return _onewire.writebyte(self.pin, value)

    def write(self, buf):
        for b in buf:
            _onewire.writebyte(self.pin, b)

    def select_rom(self, rom):
        self.reset()
        self.writebyte(MATCH_ROM)
        self.write(rom)

    def crc8(self, data):
        return _onewire.crc8(data)

    def scan(self):
        """The ROMs of the devices on the bus (the datasheets' search algorithm)."""
        found = []
        rom = bytearray(8)
        last_fork = 65  # (none yet)
        while True:
            rom, last_fork = self._search(rom, last_fork)
            if rom is None:
                return found
            found.append(rom)  # (a bytearray, a new one each search, as micropython-lib's)
            if last_fork == 0:
                return found

    def _search(self, prev, prev_fork):
        if not self.reset():
            return None, 0
        self.writebyte(SEARCH_ROM)
        rom = bytearray(8)
        fork = 0
        for index in range(64):
            byte, mask = index // 8, 1 << (index % 8)
            bit = _onewire.readbit(self.pin)
            complement = _onewire.readbit(self.pin)
            if bit and complement:
                return None, 0  # (nobody left in the search)
            if not bit and not complement:  # both values present: a fork
                if index + 1 < prev_fork:
                    bit = 1 if prev[byte] & mask else 0
                    if not bit:
                        fork = index + 1
                elif index + 1 == prev_fork:
                    bit = 1
                else:
                    bit = 0
                    fork = index + 1
            if bit:
                rom[byte] |= mask
            _onewire.writebit(self.pin, bit)
        return rom, fork
