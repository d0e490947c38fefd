"""Part ``vl53l0x``: an ST VL53L0X-class time-of-flight ranger on I2C (address 0x29),
casting a ray from its mount (:class:`sim_plant.sonars.BeamRangeModel`, as the other
rangers do) at the end of each measurement.

The VL53L0X's registers are not documented (ST ships an API); the model answers the ones
the published drivers (Pololu's, Adafruit's and their MicroPython ports) use:
identification (0xC0 reads 0xEE, 0xC1 0xAA, 0xC2 0x10), SYSRANGE_START (0x00: bit 0
starts one measurement and reads back 0 once it has started; bit 1, back-to-back: one
after another until 0x00 is written), RESULT_INTERRUPT_STATUS (0x13: 0x04 when a
measurement is ready), RESULT_RANGE_STATUS (0x14: its bits 6:3 are 11, a valid range, or
4, out of range) with the range in mm at 0x1E..0x1F (big-endian; 8190 out of range),
SYSTEM_INTERRUPT_CLEAR (0x0B: writing bit 0 clears the ready flag), and the two handshakes
of the drivers' start-up (0x83 reads non-zero, 0x92 the SPAD count and type), and the
GPIO1 interrupt pin (``<name>.gpio1``): asserted while a range is ready when
SYSTEM_INTERRUPT_CONFIG_GPIO (0x0A) is 4, active high while GPIO_HV_MUX_ACTIVE_HIGH (0x84)
has bit 4 set (its power-on value, 0x11; the drivers clear it: active low). Each
measurement takes ``budget_us`` (the chip's timing budget: 33 ms by default); a driver's
writes that set another budget are stored but not decoded. Every other register is plain
memory.

Range limits: ``min_range_m`` to ``max_range_m`` (the datasheet's default mode: up to 1.2 m indoors on
a white target); beyond, no target (8190). Noise: ``noise_sd_m`` plus ``noise_fraction`` of
the range (the datasheet's ranging accuracy: about 3 % at 1.2 m). Not modelled: ``NOT_MODELLED`` (docs/parts.md)."""

from sim_plant.buses import NEVER_US, BusName, Change, RegisterDevice, check_placement
from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.option_table import Num
from sim_plant.sonars import BeamRangeModel

SYSRANGE_START, INTERRUPT_CLEAR, INTERRUPT_STATUS, RANGE_STATUS, RANGE_MM = 0x00, 0x0B, 0x13, 0x14, 0x1E
HANDSHAKE, SPAD_INFO = 0x83, 0x92
GPIO_CONFIG, GPIO_HV_MUX = 0x0A, 0x84  # SYSTEM_INTERRUPT_CONFIG_GPIO (4: new sample ready), its polarity (bit 4: high)
OUT_OF_RANGE_MM = 8190
VALID, NO_TARGET = 11, 4  # RESULT_RANGE_STATUS bits 6:3


class TofRanging:
    """What the ST time-of-flight rangers' chips share (the VL53L1X's too): GPIO1's output, a
    ray cast at each measurement's end with its noise, and the truth they report."""

    def initial_outputs(self) -> dict:
        return {self.gpio_signal: self.gpio_level}

    def _plan(self, t_us: int) -> None:
        """The next event: GPIO1's change now, else the measurement's end."""
        self.next_us = t_us if self.gpio_line() != self.gpio_level else self.measure_us

    def fire(self, t_us, plant, out) -> None:
        if t_us >= self.measure_us:
            self._measure(t_us, plant)
        level = self.gpio_line()
        if level != self.gpio_level:
            self.gpio_level = level
            out.append(Change(t_us, self.gpio_signal, level))
        self._plan(t_us)

    def _range(self, t_us, plant):
        """The ray's reading in metres with its noise, or None (no target); keeps the truth."""
        self.true_m, reading = self.model.measure(t_us, plant.pose_at(t_us), plant.world, plant.rng)
        if reading is not None and self.noise_fraction:
            reading = max(self.model.min_m, reading + plant.rng.normal(0.0, self.noise_fraction * self.true_m))
        self.reading_m = float("nan") if reading is None else reading
        return reading

    def truth(self, t_us, plant) -> dict:
        return {
            f"{self.label}_range_m": self.true_m,
            f"{self.label}_reading_m": self.reading_m,
            f"{self.label}_measurements": self.measurements,
        }


def check_ranges(options: dict, what: str) -> None:
    """A ranger part's placement and range limits, checked."""
    check_placement(options, what)
    if options["min_range_m"] >= options["max_range_m"]:
        raise ValueError(
            f"min_range_m: expected less than max_range_m ({options['max_range_m']}), got {options['min_range_m']}"
        )


def beam_model(part: PartType) -> BeamRangeModel:
    """The ray a ranger part casts from its mount, with its options' limits and noise."""
    o = part.options
    return BeamRangeModel(
        part.mount_rad(), noise_sd_m=o["noise_sd_m"], min_m=o["min_range_m"], max_m=o["max_range_m"], no_echo="none"
    )


class Vl53l0xChip(TofRanging, RegisterDevice):
    RESET = {0xC0: 0xEE, 0xC1: 0xAA, 0xC2: 0x10, 0x8A: 0x29, SPAD_INFO: 0x85, GPIO_HV_MUX: 0x11}
    FIXED_STATE = (*RegisterDevice.FIXED_STATE, "model", "budget_us", "noise_fraction")
    MODELLED = {
        SYSRANGE_START: "SYSRANGE_START: bit 0 one measurement (reads 0 once started), bit 1 back-to-back",
        GPIO_CONFIG: "SYSTEM_INTERRUPT_CONFIG_GPIO: 4, GPIO1 says a range is ready",
        INTERRUPT_CLEAR: "SYSTEM_INTERRUPT_CLEAR: bit 0 clears the ready flag",
        INTERRUPT_STATUS: "RESULT_INTERRUPT_STATUS: 0x04 when a range is ready",
        RANGE_STATUS: "RESULT_RANGE_STATUS and the range (0x1E..0x1F)",
        **{reg: "identification (0xEE, 0xAA, 0x10)" for reg in (0xC0, 0xC1, 0xC2)},
        0x8A: "I2C_SLAVE_DEVICE_ADDRESS (plain)",
        HANDSHAKE: "the start-up handshake (reads non-zero)",
        SPAD_INFO: "the SPAD count and type",
        GPIO_HV_MUX: "GPIO_HV_MUX_ACTIVE_HIGH: bit 4, GPIO1's polarity",
    }

    def __init__(self, name, bus, address, model: BeamRangeModel, budget_us: int, noise_fraction: float):
        super().__init__(name, bus, address)
        self.model = model
        self.budget_us = int(budget_us)
        self.noise_fraction = float(noise_fraction)
        self.next_us = NEVER_US
        self.measure_us = NEVER_US  # the running measurement's end
        self.gpio_signal = f"{name}.gpio1"
        self.outputs = {self.gpio_signal: "level"}
        self.gpio_level = self.gpio_line()
        self.true_m = float("nan")
        self.reading_m = float("nan")
        self.measurements = 0

    def gpio_line(self) -> int:
        """GPIO1's level: asserted (its polarity) while a sample is ready and configured to say so."""
        active = bool(self.regs[INTERRUPT_STATUS] & 0x07) and self.regs[GPIO_CONFIG] & 0x07 == 0x04
        return int(active == bool(self.regs[GPIO_HV_MUX] & 0x10))

    def load(self, t_us, reg):
        if reg == HANDSHAKE:
            return self.regs[HANDSHAKE] or 0x10
        return self.regs[reg]

    def store(self, t_us, reg, value):
        if reg in (0xC0, 0xC1, 0xC2, INTERRUPT_STATUS, RANGE_STATUS) or RANGE_STATUS < reg < 0x20:
            return  # read-only
        if reg == INTERRUPT_CLEAR:
            if value & 0x01:
                self.regs[INTERRUPT_STATUS] = 0
            self.regs[reg] = value
        elif reg == SYSRANGE_START:
            self.regs[reg] = value & 0x02  # (bit 0 reads back 0: the measurement started)
            if value & 0x03:
                if self.measure_us == NEVER_US:
                    self.measure_us = t_us + self.budget_us
            else:
                self.measure_us = NEVER_US  # stopped
        else:
            self.regs[reg] = value & 0xFF
        self._plan(t_us)

    def _measure(self, t_us, plant) -> None:
        reading = self._range(t_us, plant)
        mm = OUT_OF_RANGE_MM if reading is None else round(reading * 1000)
        self.regs[RANGE_STATUS] = (VALID if reading is not None else NO_TARGET) << 3 | 0x01
        self.regs[RANGE_MM], self.regs[RANGE_MM + 1] = mm >> 8 & 0xFF, mm & 0xFF
        self.regs[INTERRUPT_STATUS] = 0x04
        self.measurements += 1
        self.measure_us = t_us + self.budget_us if self.regs[SYSRANGE_START] & 0x02 else NEVER_US


class Vl53l0x(PartType):
    CHIP = Vl53l0xChip  # (its registers: docs/parts.md)
    kind = "vl53l0x"
    MODELLED_FEATURES = (
        "a ray from the mount to the walls each measurement, within its range limits, with noise",
        "the registers the published drivers use: identification, single and back-to-back ranging, the ready "
        "flag and its clear, the start-up handshakes",
        "the GPIO1 interrupt pin and its polarity",
    )
    NOT_MODELLED = (
        "the timed (inter-measurement) mode",
        "the timing budget written through registers (a budget is the part's option)",
        "the GPIO1 thresholds",
        "the signal rate and ambient light",
        "cross-talk",
        "a target's reflectance",
    )
    doc = "A VL53L0X-class time-of-flight ranger on I2C (0xC0 reads 0xEE): a ray from its mount each measurement."
    OPTIONS = (
        Opt("bus", BusName(), "i2c0", "the bus it is on, as the firmware creates it"),
        Opt("address", Num("", 0, 127, whole=True), 0x29, "its 7-bit I2C address (0x29 at power-on)"),
        Opt(
            "budget_us",
            Num("microseconds", 20_000, 1_000_000, whole=True),
            33_000,
            "how long a measurement takes (the chip's timing budget)",
        ),
        Opt("min_range_m", Num("metres", 0, 1), 0.03, "nearer than this reads this"),
        Opt("max_range_m", Num("metres", 0.1, 4), 1.2, "farther than this: no target (8190 mm)"),
        Opt("noise_sd_m", Num("metres", 0, 1), 0.003, "the noise at any range (standard deviation)"),
        Opt("noise_fraction", Num("", 0, 1), 0.01, "and the noise as a fraction of the range"),
    )
    SIGNALS = (
        Sig(
            "gpio1",
            "out",
            "level",
            "the interrupt pin: asserted while a range is ready (0x0A = 4; 0x84 bit 4: active high)",
        ),
    )
    TRUTH = ("{name}_range_m", "{name}_reading_m", "{name}_measurements")
    VIEWS = (View("range", "the range the chip measured against the true range", truth=TRUTH[:2]),)
    on_bus = True
    needs_body = True

    def check(self) -> None:
        check_ranges(self.options, "the VL53L0X")

    def add(self, build: Build) -> None:
        o = self.options
        model = beam_model(self)
        build.parts.append(Vl53l0xChip(self.name, o["bus"], o["address"], model, o["budget_us"], o["noise_fraction"]))
