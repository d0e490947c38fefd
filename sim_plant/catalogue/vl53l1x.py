"""Part ``vl53l1x``: an ST VL53L1X time-of-flight ranger on I2C (address 0x29), with 16-bit
register addresses (the two bytes after the chip's address, high byte first; each byte read
or written after them moves the address on), casting a ray from its mount
(:class:`sim_plant.sonars.BeamRangeModel`, as the other rangers do) at the end of each
measurement.

ST documents the registers its ULD driver (STSW-IMG009) uses; the model answers those the
drivers (the ULD, Pololu's, and the MicroPython ports) read and act on: the model id at
0x010F (0xEA, then the module type 0xCC at 0x0110), FIRMWARE__SYSTEM_STATUS (0x00E5: bit 0
set once the chip has booted, ``BOOT_US`` after power-on or after SOFT_RESET (0x0000) is
written 1 again; written 0, the chip is held in reset: its registers back to their power-on
values, every other write ignored), SYSTEM__MODE_START (0x0087: 0x40 ranges one measurement
after another, each ``budget_us`` long; 0x10 one measurement; 0x00 stops), GPIO_HV_MUX__CTRL
(0x0030: bit 4, the interrupt's polarity: 0 active high, its power-on value),
GPIO__TIO_HV_STATUS (0x0031: bit 0 is the interrupt line, asserted while a range is ready),
SYSTEM__INTERRUPT_CLEAR (0x0086: bit 0 clears the ready flag), RESULT__RANGE_STATUS (0x0089:
bits 4:0 are 9 for a valid range, 4, a signal failure, with no target in range), its stream
count (0x008B: one more per measurement), and the range in mm at 0x0096..0x0097 (big-endian;
0 with no target). The GPIO1 interrupt pin (``<name>.gpio1``) follows 0x0031's bit 0. Every
other register is plain memory (the drivers' 91-byte default configuration at 0x002D lands
there, its timing and distance-mode registers stored, not decoded).

Range limits: ``min_range_m`` to ``max_range_m`` (the datasheet's long distance mode: up to
4 m in the dark); beyond, no target. Noise: ``noise_sd_m`` plus ``noise_fraction`` of the
range. Not modelled: ``NOT_MODELLED`` (docs/parts.md)."""

from sim_plant.buses import NEVER_US, BusDevice, BusName
from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.catalogue.vl53l0x import TofRanging, beam_model, check_ranges
from sim_plant.option_table import Num
from sim_plant.sonars import BeamRangeModel

SOFT_RESET, GPIO_HV_MUX, TIO_HV_STATUS = 0x0000, 0x0030, 0x0031
INTERRUPT_CLEAR, MODE_START, RANGE_STATUS, STREAM_COUNT, RANGE_MM = 0x0086, 0x0087, 0x0089, 0x008B, 0x0096
SYSTEM_STATUS, MODEL_ID = 0x00E5, 0x010F
BOOT_US = 1_200  # the datasheet's boot time (tBOOT)
VALID, SIGNAL_FAIL = 9, 4  # RESULT__RANGE_STATUS bits 4:0 as the chip gives them (the ULD maps them to 0 and 2)
RESET = {SOFT_RESET: 0x01, 0x0001: 0x29, GPIO_HV_MUX: 0x01, MODEL_ID: 0xEA, MODEL_ID + 1: 0xCC}
READ_ONLY = frozenset((TIO_HV_STATUS, SYSTEM_STATUS, MODEL_ID, MODEL_ID + 1, *range(RANGE_STATUS, 0x00B0)))


class Vl53l1xChip(TofRanging, BusDevice):
    FIXED_STATE = (*BusDevice.FIXED_STATE, "model", "budget_us", "noise_fraction", "gpio_signal")

    def __init__(self, name, bus, address, model: BeamRangeModel, budget_us: int, noise_fraction: float):
        super().__init__(name, bus, address)
        self.model = model
        self.budget_us = int(budget_us)
        self.noise_fraction = float(noise_fraction)
        self.gpio_signal = f"{name}.gpio1"
        self.outputs = {self.gpio_signal: "level"}
        self.pointer, self.address_bytes = 0, 0
        self.true_m = float("nan")
        self.reading_m = float("nan")
        self.measurements = 0
        self.power_on(0)
        self.gpio_level = self.gpio_line()

    def power_on(self, t_us: int) -> None:
        self.regs = dict(RESET)  # register -> value (the others read 0)
        self.booted_us = t_us + BOOT_US
        self.ready = False
        self.measure_us = NEVER_US
        self.next_us = NEVER_US

    def gpio_line(self) -> int:
        """The interrupt line (GPIO1, 0x0031 bit 0): asserted while a range is ready, high unless 0x0030 bit 4."""
        return int(self.ready != bool(self.regs[GPIO_HV_MUX] & 0x10))

    # -- I2C: two address bytes, then data ------------------------------------------

    def begin(self, t_us, reading):
        if not reading:
            self.address_bytes = 0

    def write(self, t_us, byte):
        if self.address_bytes < 2:
            self.pointer = self.pointer | byte if self.address_bytes else byte << 8
            self.address_bytes += 1
            return True
        self._store(t_us, self.pointer, byte)
        self.pointer = (self.pointer + 1) & 0xFFFF
        return True

    def read(self, t_us):
        value = self._load(t_us, self.pointer)
        self.pointer = (self.pointer + 1) & 0xFFFF
        return value

    def _load(self, t_us, reg) -> int:
        if reg == SYSTEM_STATUS:
            return int(self.regs[SOFT_RESET] & 0x01 and t_us >= self.booted_us)
        if reg == TIO_HV_STATUS:
            return self.gpio_line()
        return self.regs.get(reg, 0)

    def _store(self, t_us, reg, value) -> None:
        if reg in READ_ONLY or reg != SOFT_RESET and not self.regs[SOFT_RESET] & 0x01:
            return  # (held in reset: only SOFT_RESET is heard)
        if reg == SOFT_RESET:
            if not value & 0x01:
                self.power_on(t_us)  # held in reset
            elif not self.regs[SOFT_RESET] & 0x01:
                self.booted_us = t_us + BOOT_US
            self.regs[SOFT_RESET] = value & 0x01
        elif reg == INTERRUPT_CLEAR:
            if value & 0x01:
                self.ready = False
        elif reg == MODE_START:
            self.regs[reg] = value
            if value & 0x50:
                if self.measure_us == NEVER_US:
                    self.measure_us = max(t_us, self.booted_us) + self.budget_us
            else:
                self.measure_us = NEVER_US
        else:
            self.regs[reg] = value & 0xFF
        self._plan(t_us)

    # -- measuring --------------------------------------------------------------------

    def _measure(self, t_us, plant) -> None:
        reading = self._range(t_us, plant)
        mm = 0 if reading is None else round(reading * 1000)
        self.regs[RANGE_STATUS] = VALID if reading is not None else SIGNAL_FAIL
        self.regs[STREAM_COUNT] = (self.regs.get(STREAM_COUNT, 0) + 1) & 0xFF
        self.regs[RANGE_MM], self.regs[RANGE_MM + 1] = mm >> 8 & 0xFF, mm & 0xFF
        self.ready = True
        self.measurements += 1
        self.measure_us = t_us + self.budget_us if self.regs[MODE_START] & 0x40 else NEVER_US


class Vl53l1x(PartType):
    kind = "vl53l1x"
    MODELLED_FEATURES = (
        "16-bit register addresses; boot time, SOFT_RESET, the model and module type",
        "a ray from the mount each measurement (back to back, or one), the range status, the stream count, "
        "the interrupt and its clear and polarity",
        "the GPIO1 interrupt pin",
    )
    NOT_MODELLED = (
        "the short and medium distance modes' own limits (the long mode's)",
        "the inter-measurement period (measurements follow one another)",
        "the region of interest",
        "the thresholds",
        "the signal rate and ambient light",
        "a target's reflectance",
        "the default configuration's timing and distance-mode registers (stored, not decoded)",
    )
    doc = (
        "A VL53L1X time-of-flight ranger on I2C, 16-bit registers (0x010F reads 0xEA): a ray from its mount each range."
    )
    OPTIONS = (
        Opt("bus", BusName(), "i2c0", "the bus it is on, as the firmware creates it"),
        Opt("address", Num("", 0, 127, whole=True), 0x29, "its 7-bit I2C address (0x29 at power-on)"),
        Opt(
            "budget_us",
            Num("microseconds", 15_000, 1_000_000, whole=True),
            100_000,
            "how long a measurement takes (the chip's timing budget: the drivers' default 100 ms)",
        ),
        Opt("min_range_m", Num("metres", 0, 1), 0.04, "nearer than this reads this"),
        Opt("max_range_m", Num("metres", 0.1, 4), 4.0, "farther than this: no target (a signal failure)"),
        Opt("noise_sd_m", Num("metres", 0, 1), 0.005, "the noise at any range (standard deviation)"),
        Opt("noise_fraction", Num("", 0, 1), 0.005, "and the noise as a fraction of the range"),
    )
    SIGNALS = (Sig("gpio1", "out", "level", "the interrupt pin: asserted while a range is ready (0x0030 bit 4: low)"),)
    TRUTH = ("{name}_range_m", "{name}_reading_m", "{name}_measurements")
    VIEWS = (View("range", "the range the chip measured against the true range", truth=TRUTH[:2]),)
    on_bus = True
    needs_body = True

    def check(self) -> None:
        check_ranges(self.options, "the VL53L0X")

    def add(self, build: Build) -> None:
        o = self.options
        model = beam_model(self)
        build.parts.append(Vl53l1xChip(self.name, o["bus"], o["address"], model, o["budget_us"], o["noise_fraction"]))
