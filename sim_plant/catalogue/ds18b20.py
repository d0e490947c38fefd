"""Part ``ds18b20``: a DS18B20 temperature sensor on a 1-Wire line, answered slot by slot:
the board's ``_onewire`` (MicroPython's extmod/modonewire.c; ``host/shim/_onewire.py``)
sends each reset, written bit or byte and read bit or byte to the pin's line,
``onewire:<gpio>``, and the part answers as the datasheet's state machine does.

Its 64-bit ROM: family 0x28, the 48-bit ``serial`` (least significant byte first), the
Dallas CRC-8 of those 7 bytes. ROM commands: READ ROM (0x33), MATCH ROM (0x55), SKIP ROM
(0xCC), SEARCH ROM (0xF0; ALARM SEARCH, 0xEC, takes part when the last temperature is
above TH or below TL). Function commands: CONVERT T (0x44; read slots give 0 until it is
done: 93.75, 187.5, 375 or 750 ms at 9, 10, 11, 12 bits), READ SCRATCHPAD (0xBE: 9 bytes,
the last their CRC), WRITE SCRATCHPAD (0x4E: TH, TL, configuration), COPY SCRATCHPAD
(0x48), RECALL E2 (0xB8), READ POWER SUPPLY (0xB4: 1, powered). At power-on the
temperature register reads 85 °C. The temperature converted is the option
``temperature_c``, or what a scenario's set-control ``temperature`` set last, taken at the
conversion's start and rounded to the resolution. One part per line (several on one line,
a real bus's wired-AND, are not modelled); not modelled: ``NOT_MODELLED`` (docs/parts.md)."""

from sim_plant.buses import BusDevice, BusName
from sim_plant.catalogue.base import Build, Opt, PartType
from sim_plant.controls import Control
from sim_plant.option_table import Num

LINE_ADDRESS = 0x40  # (the one device on its line answers the shim's slots here)
FAMILY = 0x28
# (the line's operations, host/shim/_onewire.py: one transfer each, the operation's byte first)
RESET, WRITE_BIT, WRITE_BYTE, READ_BIT, READ_BYTE = range(5)
SLOT_US = 70  # a bit's time slot (modonewire.c's TIMING_READ1..3, TIMING_WRITE1..3)
SAMPLE_US = 15  # where in a read slot the master samples the line
CONVERSION_US = {9: 93_750, 10: 187_500, 11: 375_000, 12: 750_000}  # datasheet, tCONV


def crc8(data: bytes) -> int:
    """The Dallas/Maxim CRC-8 (x^8 + x^5 + x^4 + 1, least significant bit first)."""
    crc = 0
    for byte in data:
        for _ in range(8):
            mix = (crc ^ byte) & 1
            crc >>= 1
            if mix:
                crc ^= 0x8C
            byte >>= 1
    return crc


def rom_of(serial: int) -> bytes:
    body = bytes((FAMILY,)) + serial.to_bytes(6, "little")
    return body + bytes((crc8(body),))


def raw_temperature(temperature_c: float, bits: int) -> int:
    """The temperature register (1/16 °C, two's complement, 16 bits) at ``bits`` of
    resolution: the bits below it read 0 (the datasheet calls them undefined)."""
    t = min(max(temperature_c, -55.0), 125.0)
    raw = round(t * 16) & ~((1 << (12 - bits)) - 1)
    return raw & 0xFFFF


class Ds18b20Chip(BusDevice):
    FIXED_STATE = (*BusDevice.FIXED_STATE, "rom", "temperature_c")

    def __init__(self, name: str, line: str, rom: bytes, temperature_c: float, controls=None):
        super().__init__(name, line, LINE_ADDRESS)
        self.rom, self.temperature_c, self.controls = rom, temperature_c, controls
        self.eeprom = [0x4B, 0x46, 0x7F]  # TH, TL, configuration (12 bits) as shipped
        self.th, self.tl, self.config = self.eeprom
        self.raw = 0x0550  # 85 °C until the first conversion
        self.done_at = 0
        self.pending = self.raw
        self.converting = False
        self.conversions = 0
        self.last_c = 85.0
        self.op = None
        self.reply = 1
        self._idle()

    # -- the line's operations (one BUS transfer each) ---------------------------

    def begin(self, t_us, reading):
        if not reading:
            self.op = None

    def write(self, t_us, byte):
        if self.op is None:
            self.op = byte
            if byte == RESET:
                self.reply = self._reset(t_us)
            elif byte == READ_BIT:
                self.reply = self._read_bit(t_us + SAMPLE_US)
            elif byte == READ_BYTE:
                self.reply = sum(self._read_bit(t_us + i * SLOT_US + SAMPLE_US) << i for i in range(8))
            return True
        if self.op == WRITE_BIT:  # (each bit counts at its slot's end)
            self._write_bit(t_us + SLOT_US, byte & 1)
        elif self.op == WRITE_BYTE:
            for i in range(8):
                self._write_bit(t_us + (i + 1) * SLOT_US, (byte >> i) & 1)
        return True

    def read(self, t_us):
        return self.reply

    # -- the datasheet's state machine, a time slot at a time ----------------------

    def _idle(self):
        self.mode = "idle"  # after a reset: "rom" (a ROM command's bits), then per command
        self.bits_in = []
        self.out = []  # bits the device sends in the next read slots
        self.search = (0, 0)  # (bit index, phase: 0 its bit, 1 the complement, 2 the master's)

    def _reset(self, t_us) -> int:
        self._idle()
        self.mode = "rom"
        return 1  # presence

    def _bits(self, data: bytes) -> list:
        return [(b >> i) & 1 for b in data for i in range(8)]

    def _read_bit(self, t_us) -> int:
        if self.mode == "search":
            return self._search_read()
        if self.out:
            return self.out.pop(0)
        if self.mode == "convert":
            self._settle(t_us)
            return 0 if self.converting else 1
        if self.mode == "power":
            return 1
        return 1  # (nothing to send: the line stays high)

    def _write_bit(self, t_us, bit: int) -> None:
        if self.mode == "search":
            self._search_write(bit)
            return
        if self.mode not in ("rom", "function", "match", "write"):
            return  # (idle or sending: a written 1 is a read slot the device ignores)
        self.bits_in.append(bit)
        if self.mode == "match" and len(self.bits_in) == 64:
            self.mode = "function" if bytes(self._bytes(self.bits_in)) == self.rom else "idle"
            self.bits_in = []
        elif self.mode == "write" and len(self.bits_in) == 24:
            self.th, self.tl, self.config = self._bytes(self.bits_in)
            self.config = (self.config & 0x60) | 0x1F
            self.mode, self.bits_in = "idle", []
        elif self.mode in ("rom", "function") and len(self.bits_in) == 8:
            command = self._bytes(self.bits_in)[0]
            self.bits_in = []
            (self._rom_command if self.mode == "rom" else self._function)(t_us, command)

    @staticmethod
    def _bytes(bits: list) -> list:
        return [sum(bits[i + j] << j for j in range(8)) for i in range(0, len(bits), 8)]

    def _rom_command(self, t_us, command: int) -> None:
        if command == 0x33:
            self.mode, self.out = "function", self._bits(self.rom)
        elif command == 0x55:
            self.mode = "match"
        elif command == 0xCC:
            self.mode = "function"
        elif command == 0xF0 or (command == 0xEC and self._alarm()):
            self.mode, self.search = "search", (0, 0)
        else:
            self.mode = "idle"

    def _alarm(self) -> bool:
        t = self.raw - 0x10000 if self.raw & 0x8000 else self.raw
        th = self.th - 256 if self.th & 0x80 else self.th
        tl = self.tl - 256 if self.tl & 0x80 else self.tl
        return t >> 4 >= th or t >> 4 <= tl

    def _search_read(self) -> int:
        index, phase = self.search
        if index >= 64 or phase == 2:
            return 1
        bit = (self.rom[index // 8] >> (index % 8)) & 1
        self.search = (index, phase + 1)
        return bit if phase == 0 else bit ^ 1

    def _search_write(self, bit: int) -> None:
        index, _phase = self.search
        if index >= 64:
            return
        mine = (self.rom[index // 8] >> (index % 8)) & 1
        if bit != mine:
            self._idle()  # (it leaves the search until the next reset)
            return
        self.search = (index + 1, 0)
        if index + 1 == 64:
            self.mode = "function"

    def _function(self, t_us, command: int) -> None:
        if command == 0x44:
            self._settle(t_us)
            bits = 9 + ((self.config >> 5) & 3)
            self.last_c = self._temperature(t_us)
            self.pending = raw_temperature(self.last_c, bits)
            self.done_at = t_us + CONVERSION_US[bits]
            self.converting = True
            self.conversions += 1
            self.mode = "convert"
        elif command == 0xBE:
            self._settle(t_us)
            pad = bytes((self.raw & 0xFF, self.raw >> 8, self.th, self.tl, self.config, 0xFF, 0x0C, 0x10))
            self.mode, self.out = "idle", self._bits(pad + bytes((crc8(pad),)))
        elif command == 0x4E:
            self.mode = "write"
        elif command == 0x48:
            self.eeprom = [self.th, self.tl, self.config]
            self.mode = "idle"
        elif command == 0xB8:
            self.th, self.tl, self.config = self.eeprom
            self.mode = "idle"
        elif command == 0xB4:
            self.mode = "power"
        else:
            self.mode = "idle"

    def _temperature(self, t_us) -> float:
        if self.controls is None:
            return self.temperature_c
        return self.controls.value_at(self.label, "temperature", t_us, self.temperature_c)

    def _settle(self, t_us) -> None:
        if self.converting and t_us >= self.done_at:
            self.raw, self.converting = self.pending, False

    def truth(self, t_us, plant) -> dict:
        return {f"{self.label}_conversions": self.conversions, f"{self.label}_temperature_c": self.last_c}


class Ds18b20(PartType):
    kind = "ds18b20"
    MODELLED_FEATURES = (
        "the 64-bit ROM and its CRC; READ, MATCH, SKIP, SEARCH and ALARM SEARCH ROM",
        "CONVERT T with its time per resolution, the scratchpad and its CRC, COPY and RECALL, READ POWER "
        "SUPPLY; 85 °C at power-on",
    )
    NOT_MODELLED = (
        "several sensors on one line (one part per line)",
        "parasite power",
        "accuracy",
        "the EEPROM's write time",
    )
    doc = "A DS18B20 temperature sensor on a 1-Wire pin (MicroPython's onewire and ds18x20 modules)."
    OPTIONS = (
        Opt("bus", BusName(), "onewire:4", "its data line as the shim names it: onewire:<the GPIO's number>"),
        Opt("serial", Num("48-bit serial", 0, (1 << 48) - 1, whole=True), 0x0000_0B1E_5EED, "its ROM's serial number"),
        Opt("temperature_c", Num("degrees C", -55, 125), 22.5, "what it measures"),
    )
    SIGNALS = ()
    TRUTH = ("{name}_conversions", "{name}_temperature_c")
    VIEWS = ()
    CONTROLS = (Control("temperature", Num("°C", -55, 125), "the temperature it measures from then on"),)
    on_bus = True

    def check(self) -> None:
        if not self.options["bus"].startswith("onewire:"):
            raise ValueError(f"bus: expected onewire:<gpio> (its data line), got {self.options['bus']}")

    def add(self, build: Build) -> None:
        o = self.options
        rom = rom_of(int(o["serial"]))
        build.parts.append(Ds18b20Chip(self.name, o["bus"], rom, float(o["temperature_c"]), build.controls))
