"""Chips on a bus: the register-level device framework and the buses' byte-level rules
(``docs/shim.md``, "Buses"; ``docs/parts.md``).

A :class:`BusDevice` is an engine part on a named bus (``i2c0``, ``spi1``, a SoftI2C's
``i2c:<scl>,<sda>``) at a 7-bit address, or, on SPI, selected by its chip-select input
(``<name>.cs``, low: selected; or tied low by the rig, ``cs = "low"``: selected for
good) and, its clock input (``<name>.sck``) wired to a pin, clocked only while that pin is
the SPI's (parts that share MOSI with a clock pin each: docs/wiring.md). Chip select is
active low and a selection lasts from its fall to its rise, however many transfers it
spans: the bytes clocked while it is low reach the chip, as one stream (a display takes
commands and data on; a register chip takes the register address as the first byte after
the fall only, so a register chip whose CS never rises reads or writes on from the first
address, as the silicon does). :class:`RegisterDevice` adds a register file (a list of
256 ints, so that a plant snapshot copies it), an identity register, a register pointer
that auto-increments, and hooks for the registers a chip computes (its samples) or acts
on (a reset bit). :class:`BusSet` holds a plant's devices by bus and plays each
transfer the shim sends byte by byte against them, as the wire would.

A transfer happens at one instant (its start, the plant's time): a multi-byte read is one
coherent sample, as a chip's block-data update gives.

What a chip does on its own time is declared, not coded per chip: its ``SELF_CLEARING``
bits (:class:`SelfClearing`: a BOOT, a SW_RESET, a REBOOT reads back set until the
datasheet's time has passed in virtual time, then clear), its ``DATA_READY`` status bits
(:class:`DataReady`: set at each tick of the output data rate, cleared when the registers
the datasheet names are read; an overrun bit when a sample was overwritten unread) and
its ``MODELLED`` registers
(name -> what of it the model honours). A write to a register not in ``MODELLED`` is
kept as plain memory, counted in :attr:`RegisterDevice.unmodelled` and named once per
chip in the run's output (:meth:`RegisterDevice.take_notes`).
"""

import re
from dataclasses import dataclass

from sim_plant.engine import Part
from sim_plant.plant import NEVER_US, Change

# ops and statuses, as the link codec names them (host/shim/_hilframe.py: BUS_*)
XFER, XFER_NOSTOP, START, WRITE, READ, READ_ACK, STOP, SPI_XFER, SCAN = range(9)
OK, NACK_ADDRESS, NACK_DATA, STUCK = range(4)
FIRST_ADDRESS, LAST_ADDRESS = 0x08, 0x77
"""The 7-bit addresses a device may have (the others are reserved by the I2C standard)."""


class BusDevice(Part):
    """A chip on a bus. I2C: :meth:`begin` (its address matched) then :meth:`write` /
    :meth:`read` a byte at a time, :meth:`end` at the stop. SPI: :meth:`select`,
    :meth:`exchange` a byte at a time, :meth:`transferred` at the end of each transfer
    (chip select may stay low: the selection goes on), :meth:`deselect` when chip select
    rises; :meth:`tie_cs_low`: no chip select input, selected for good."""

    FIXED_STATE = ("inputs", "outputs", "bus", "address", "label")
    holds_bus = False  # a device that holds SDA low: every transfer on its bus times out

    def __init__(self, name: str, bus: str, address: int | None):
        self.label = name
        self.bus = bus
        self.address = address
        self.cs_signal = f"{name}.cs" if address is None else None
        self.sck_signal = f"{name}.sck" if address is None else None  # (SPI: its clock's pin, SCK_SIGNAL)
        self.inputs = {self.cs_signal: "level", self.sck_signal: "level"} if self.cs_signal else {}
        self.outputs = {}
        self.selected = False

    def set_input(self, name: str, value, t_us: int, plant) -> bool:
        if name == self.sck_signal:
            return False  # (a level on the clock's pin as a GPIO: no SPI byte; bit-banged SPI is not modelled)
        if name != self.cs_signal:
            raise KeyError(name)
        selected = not value
        if selected and not self.selected:
            self.select(t_us)
        elif self.selected and not selected:
            self.deselect(t_us)
        self.selected = selected
        return False

    def read_block(self, t_us: int, n: int) -> bytes:
        """``n`` bytes read in one I2C read (a chip may read a block at once, as these would)."""
        if n == 1:  # (a status register polled)
            return bytes((self.read(t_us),))
        return bytes([self.read(t_us) for _ in range(n)])

    def tie_cs_low(self, t_us: int = 0) -> None:
        """Chip select tied to ground (a rig's ``cs = "low"``): no input, selected from power-on."""
        if self.cs_signal is None:
            return
        self.inputs = {k: v for k, v in self.inputs.items() if k != self.cs_signal}
        self.cs_signal = None
        self.selected = True
        self.select(t_us)

    def initial_outputs(self) -> dict:
        return {}

    # I2C
    def begin(self, t_us: int, reading: bool) -> None:
        pass

    def write(self, t_us: int, byte: int) -> bool:
        return True

    def read(self, t_us: int) -> int:
        return 0xFF

    def end(self, t_us: int) -> None:
        pass

    # SPI
    def select(self, t_us: int) -> None:
        pass

    def exchange(self, t_us: int, byte: int) -> int:
        return 0xFF

    def transferred(self, t_us: int) -> None:
        """The end of an SPI transfer while selected (chip select may stay low)."""

    def deselect(self, t_us: int) -> None:
        pass

    def take_in(self, plant) -> None:
        """Read what the chip measures from the plant as it is at a transfer's instant
        (before it: an INA219's current and voltage)."""

    # outputs that are other parts' inputs (a PWM expander's channels)
    def pass_on(self, plant) -> None:
        """Set on the plant's inputs what the last transfer changed (after it)."""


@dataclass(frozen=True)
class SelfClearing:
    """A bit the chip clears itself ``clear_us`` after the firmware writes it set.
    ``resets``: the write first puts every register back to its reset value (a software
    reset); otherwise the other registers keep what they hold (a reboot of the trimming
    memory, which "has no impact on the control registers"). ``source``: where the
    datasheet says so."""

    reg: int
    mask: int
    clear_us: int
    name: str
    resets: bool = False
    source: str = ""


@dataclass(frozen=True)
class DataReady:
    """A status bit (``mask`` of register ``reg``) set at each tick of the output data rate
    (the chip's method named ``period``: its period in µs, 0 while powered down) after the
    sample last read, cleared when a register of ``cleared_by`` is read; ``overrun_mask``:
    the bit that says a sample was overwritten before it was read (after a first read)."""

    reg: int
    mask: int
    cleared_by: tuple
    name: str
    period: str = "period_us"
    overrun_mask: int = 0
    source: str = ""


_READY_BITS: dict = {}  # id of a DATA_READY tuple -> (the tuple, {register -> (bits it holds, bits it clears)})


def _ready_bits(data_ready: tuple, reg: int) -> tuple:
    """The :class:`DataReady` bits of ``data_ready`` held in register ``reg``, and those
    a read of it clears, each in the tuple's order (found once a register)."""
    kept = _READY_BITS.get(id(data_ready))
    if kept is None or kept[0] is not data_ready:
        kept = _READY_BITS[id(data_ready)] = (data_ready, {})
    by_reg = kept[1]
    found = by_reg.get(reg)
    if found is None:
        found = by_reg[reg] = (
            tuple(bit for bit in data_ready if bit.reg == reg),
            tuple(bit for bit in data_ready if reg in bit.cleared_by),
        )
    return found


class RegisterDevice(BusDevice):
    """A device with a register file: the first byte written after its address (I2C) or
    after chip select falls (SPI, bit 7 set: a read) is the register pointer; each byte
    read or written after it moves the pointer on (auto-increment). Subclasses set
    ``RESET`` (register -> value at power-on and after a software reset), ``MODELLED``
    (register -> what of it the model honours), ``SELF_CLEARING`` and override :meth:`load`
    (a register the chip computes, read at ``t_us``) and :meth:`store` (a write the chip
    acts on)."""

    RESET: dict = {}
    MODELLED: dict = {}
    """register -> what the model honours of it (docs/parts.md lists them); the others are plain memory."""
    SELF_CLEARING: tuple = ()
    """The chip's :class:`SelfClearing` bits."""
    DATA_READY: tuple = ()
    """The chip's :class:`DataReady` status bits."""
    SPI_READ = 0x80
    FIXED_STATE = (*BusDevice.FIXED_STATE, "notes", "said")

    def __init__(self, name: str, bus: str, address: int | None):
        super().__init__(name, bus, address)
        self.regs = [0] * 256
        self.pointer = 0
        self.pointed = False  # the pointer was set in this transfer
        self.spi_read = False
        self.clearing = {}  # (reg, mask) -> the virtual time the chip clears it
        self.unmodelled = {}  # register -> (first write's t_us, writes): plain memory the firmware wrote
        self.read_ticks = {}  # a DataReady's name -> the output-data-rate tick whose sample was last read
        self.notes = []  # what the run's output is to say, taken by take_notes (never rewound)
        self.said = set()  # what was said already (never rewound: said once)
        self.power_on()

    def where(self) -> str:
        at = f"0x{self.address:02x}" if self.address is not None else "(chip select)"
        return f"{self.label} ({type(self).__name__}) on {self.bus} at {at}"

    def modelled_text(self) -> str:
        """The registers the model honours, as the run's notes name them."""
        return "; ".join(f"0x{reg:02x} {what}" for reg, what in sorted(self.MODELLED.items())) or "none"

    def take_notes(self) -> list:
        notes, self.notes[:] = list(self.notes), []
        return notes

    def _settle(self, t_us: int) -> None:
        """The self-clearing bits whose time has come read clear from now on."""
        for key, t_clear in list(self.clearing.items()):
            if t_us >= t_clear:
                reg, mask = key
                self.regs[reg] &= ~mask & 0xFF
                del self.clearing[key]

    def period_us(self) -> int:
        """The output data rate's period (0: powered down: no new samples)."""
        return 0

    def _ready(self, t_us: int, reg: int, value: int) -> int:
        """``value`` read from ``reg`` with its data-ready and overrun bits as they are at
        ``t_us``; a register that clears one marks its sample read."""
        sets, clears = _ready_bits(self.DATA_READY, reg)
        for bit in sets:
            period = getattr(self, bit.period)()
            value &= ~(bit.mask | bit.overrun_mask) & 0xFF
            if period:
                tick, last = t_us // period, self.read_ticks.get(bit.name, -1)
                value |= bit.mask if tick != last else 0
                value |= bit.overrun_mask if last >= 0 and tick - last > 1 else 0
        for bit in clears:
            period = getattr(self, bit.period)()
            self.read_ticks[bit.name] = t_us // period if period else -1
        return value

    def _written(self, t_us: int, reg: int, value: int) -> None:
        """After :meth:`store`: a self-clearing bit set starts its time; an unmodelled
        register written is counted (and named once)."""
        for bit in self.SELF_CLEARING:
            if bit.reg == reg and value & bit.mask:
                if bit.resets:
                    self.power_on()
                self.clearing[(reg, bit.mask)] = t_us + bit.clear_us
        for (bit_reg, mask), _t in self.clearing.items():
            if bit_reg == reg:  # (still running: it reads set whatever else was written)
                self.regs[reg] |= mask
        if self.MODELLED and reg not in self.MODELLED:
            first, count = self.unmodelled.get(reg, (t_us, 0))
            self.unmodelled[reg] = (first, count + 1)
            if "unmodelled" not in self.said:
                self.said.add("unmodelled")
                self.notes.append(
                    f"{self.where()}: the firmware wrote 0x{value & 0xFF:02x} to register 0x{reg:02x}, which the "
                    f"model keeps as plain memory (it honours: {self.modelled_text()}); every unmodelled "
                    "register written is listed in the trace header (unmodelled_writes)"
                )

    def power_on(self) -> None:
        self.regs = [0] * 256
        for reg, value in self.RESET.items():
            self.regs[reg] = value

    def load(self, t_us: int, reg: int) -> int:
        return self.regs[reg]

    def store(self, t_us: int, reg: int, value: int) -> None:
        self.regs[reg] = value & 0xFF

    def next_register(self, reg: int) -> int:
        return (reg + 1) & 0xFF

    def begin(self, t_us, reading):
        self.pointed = reading  # (a read goes on from the pointer as it is)

    def write(self, t_us, byte):
        if not self.pointed:
            self.pointer, self.pointed = byte, True
        else:
            reg = self.pointer
            if self.clearing:
                self._settle(t_us)
            self.store(t_us, reg, byte)
            self._written(t_us, reg, byte)
            self.pointer = self.next_register(reg)
        return True

    def read(self, t_us):
        if self.clearing:
            self._settle(t_us)
        value = self.load(t_us, self.pointer)
        if self.DATA_READY:
            value = self._ready(t_us, self.pointer, value)
        self.pointer = self.next_register(self.pointer)
        return value

    def select(self, t_us):
        self.pointed = False

    def exchange(self, t_us, byte):
        if not self.pointed:
            self.pointer, self.spi_read, self.pointed = byte & 0x7F, bool(byte & self.SPI_READ), True
            return 0x00
        if self.spi_read:
            return self.read(t_us)
        self.write(t_us, byte)
        return 0x00


class BusSet:
    """A plant's bus devices by bus name, and the state of each bus between the
    primitives of a SoftI2C (a start, the address byte, the bytes after it)."""

    FIXED_STATE = ("devices", "_buses")  # (a plant snapshot copies the SoftI2C state only)

    def __init__(self, devices: list):
        self.devices = list(devices)
        self.state = {}  # bus -> (device index or -1, expecting the address byte, reading)
        self._buses = {}  # bus -> its _Bus, made at its first transfer (the devices never change)

    def on(self, bus: str) -> tuple:
        return self.bus(bus).devices

    def bus(self, bus: str) -> "_Bus":
        """The devices on ``bus`` as a transfer looks them up (made once a bus)."""
        found = self._buses.get(bus)
        if found is None:
            found = self._buses[bus] = _Bus([d for d in self.devices if d.bus == bus])
        return found

    def transfer(self, t_us: int, bus: str, op: int, address: int, n_read: int, data: bytes, unclocked=frozenset()):
        """One BUS frame's transfer: (status, count, bytes read). SPI: to the chips selected
        (chip select low, or tied low) whose clock input is not in ``unclocked`` (the host's:
        wired to a pin that is not the SPI's at this instant, ``Wiring.unclocked``)."""
        found = self.bus(bus)
        if found.held:
            return STUCK, 0, b""
        if op == XFER or op == XFER_NOSTOP:  # (the usual transfer: one lookup by address)
            device = found.at.get(address)
            if device is None:
                return NACK_ADDRESS, 0, b""
            return self._play(t_us, device, op == XFER, n_read, data)
        devices = found.devices
        if op == SPI_XFER:
            chosen = [d for d in devices if d.selected and d.sck_signal not in unclocked]
            out = bytearray()
            for byte in data:
                value = 0xFF
                for d in chosen:  # (two selected at once: their outputs fight; the lower wins)
                    value &= d.exchange(t_us, byte)
                out.append(value)
            for d in chosen:
                d.transferred(t_us)
            return OK, len(data), bytes(out)
        if op == SCAN:
            found = sorted({d.address for d in devices if d.address is not None})
            return OK, len(found), bytes(a for a in found if FIRST_ADDRESS <= a <= LAST_ADDRESS)
        return self._primitive(t_us, bus, devices, op, n_read, data)

    @staticmethod
    def _at(devices: list, address: int):
        return next((d for d in devices if d.address == address), None)

    def _xfer(self, t_us, devices, stop, address, n_read, data):
        device = self._at(devices, address)
        if device is None:
            return NACK_ADDRESS, 0, b""
        return self._play(t_us, device, stop, n_read, data)

    @staticmethod
    def _play(t_us, device, stop, n_read, data):
        """An I2C transfer to ``device`` (its address matched): the bytes written, then
        ``n_read`` read after a repeated start, then the stop if ``stop``."""
        acks = 0
        if data or not n_read:
            device.begin(t_us, False)
            for byte in data:
                if not device.write(t_us, byte):
                    device.end(t_us)
                    return NACK_DATA, acks, b""
                acks += 1
        got = b""
        if n_read:
            device.begin(t_us, True)
            got = device.read_block(t_us, n_read)
        if stop:
            device.end(t_us)
        return OK, acks, got

    def _primitive(self, t_us, bus, devices, op, n_read, data):
        index, expecting, reading = self.state.get(bus, (-1, False, False))
        device = devices[index] if 0 <= index < len(devices) else None
        if op == START:
            self.state[bus] = (-1, True, False)
            return OK, 0, b""
        if op == STOP:
            if device is not None:
                device.end(t_us)
            self.state[bus] = (-1, False, False)
            return OK, 0, b""
        if op == WRITE:
            acks = 0
            for byte in data:
                if expecting:
                    device = self._at(devices, byte >> 1)
                    if device is None:
                        self.state[bus] = (-1, False, False)
                        return OK, acks, b""
                    reading, expecting = bool(byte & 1), False
                    index = devices.index(device)
                    device.begin(t_us, reading)
                elif device is None or reading or not device.write(t_us, byte):
                    break
                acks += 1
            self.state[bus] = (index, expecting, reading)
            return OK, acks, b""
        got = bytes(device.read(t_us) if device is not None and reading else 0xFF for _ in range(n_read))
        return OK, n_read, got


class _Bus:
    """The devices on one bus as a transfer looks them up: in order, by address (the
    first at an address answers, as :meth:`BusSet._at` finds it), whether one holds the
    bus, and those whose :meth:`~BusDevice.take_in` or :meth:`~BusDevice.pass_on` does
    something."""

    FIXED_STATE = True  # (configuration: a snapshot leaves it out)

    def __init__(self, devices: list):
        self.devices = tuple(devices)
        self.at = {}
        for d in devices:
            if d.address is not None:
                self.at.setdefault(d.address, d)
        self.held = any(d.holds_bus for d in devices)
        self.takers = tuple(d for d in devices if type(d).take_in is not BusDevice.take_in)
        self.passers = tuple(d for d in devices if type(d).pass_on is not BusDevice.pass_on)


BUS_NAME = re.compile(
    r"(i2c|spi)[0-9]|i2c:[A-Za-z0-9_]+,[A-Za-z0-9_]+|spi:[A-Za-z0-9_]+,[A-Za-z0-9_]*,[A-Za-z0-9_]*|dht:[A-Za-z0-9_]+"
    r"|onewire:[A-Za-z0-9_]+"
)  # (dht:<pin>: a DHT sensor's data line, read a frame at a time: sim_plant/catalogue/dht.py;
# onewire:<pin>: a 1-Wire line, a slot or byte at a time: sim_plant/catalogue/ds18b20.py)


@dataclass(frozen=True)
class BusName:
    """A bus as the shim names it: ``i2c0``, ``spi1`` (the board's controllers), or a
    SoftI2C's ``i2c:<scl>,<sda>`` / a SoftSPI's ``spi:<sck>,<mosi>,<miso>`` (its pins)."""

    what = "a bus name (i2c0, i2c1, spi1, i2c:<scl>,<sda>, spi:<sck>,<mosi>,<miso>, dht:<pin>, onewire:<pin>)"

    def problem(self, value):
        if isinstance(value, str) and BUS_NAME.fullmatch(value):
            return None
        return f"expected {self.what}, got {value!r}"


def address_problem(bus: str, address) -> str | None:
    """Why a device cannot sit at ``address`` on ``bus`` (None: it can)."""
    if bus.startswith("spi"):
        return (
            None if address is None else f"expected no address on SPI bus {bus} (a chip select instead), got {address}"
        )
    if address is None:
        return f"expected a 7-bit address on I2C bus {bus}, got none"
    if not FIRST_ADDRESS <= address <= LAST_ADDRESS:
        return (
            f"expected an address from 0x{FIRST_ADDRESS:02x} to 0x{LAST_ADDRESS:02x} on I2C bus {bus} "
            f"(the others are reserved), got 0x{address:02x}"
        )
    return None


def check_placement(options: dict, i2c_only: str | None = None) -> None:
    """A bus part's ``bus`` and ``address`` options (and ``spi``, for a chip on either bus):
    ValueError naming the option. ``i2c_only``: the chip's name, for a chip with no SPI."""
    bus = options["bus"]
    spi = options.get("spi", False)
    if i2c_only is not None and bus.startswith("spi"):
        raise ValueError(f"bus: expected an I2C bus ({i2c_only} has no SPI), got {bus}")
    if i2c_only is None and spi != bus.startswith("spi"):
        raise ValueError(f"spi: expected {str(not spi).lower()} on bus {bus}, got {str(spi).lower()}")
    if not spi and options.get("cs", "pin") != "pin":
        raise ValueError(f'cs: expected "pin" on I2C bus {bus} (a chip select is SPI only), got {options["cs"]!r}')
    problem = address_problem(bus, None if spi else options["address"])
    if problem:
        raise ValueError(f"address: {problem}")


def on_spi(options: dict) -> bool:
    """A bus part's options put it on SPI: its ``spi`` flag (an OLED's, an IMU's on either
    bus), or an SPI bus by its name (a chip on SPI only, an ``st7789``)."""
    return bool(options.get("spi") or str(options.get("bus", "")).startswith("spi"))


def chip_select(device: BusDevice, options: dict) -> BusDevice:
    """``device`` with its chip select as the part's ``cs`` option says (tied low: no input)."""
    if on_spi(options) and options.get("cs") == "low":
        device.tie_cs_low()
    return device


def tick_after(t_us: int, period_us: int) -> int:
    """The first output-data-rate tick strictly after ``t_us`` (ticks at multiples)."""
    return (t_us // period_us + 1) * period_us


__all__ = [
    "NEVER_US",
    "BusDevice",
    "BusName",
    "BusSet",
    "DataReady",
    "Change",
    "RegisterDevice",
    "SelfClearing",
    "address_problem",
    "check_placement",
    "chip_select",
    "on_spi",
    "tick_after",
]
