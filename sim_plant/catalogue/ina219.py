"""Part ``ina219``: a TI INA219-class current and bus-voltage monitor on I2C (address 0x40
to 0x4F by its A0/A1 pins; 0x40 by default), its shunt in the supply of the robot: the bus
voltage is the ``battery`` part's (or ``bus_v`` without one), the current ``idle_a`` plus
``motor_a`` for each motor at full speed, in proportion to its wheel's speed (the plant
keeps no motor current: the same load the battery part drains by).

Registers, 16 bits big-endian, as the datasheet gives them: configuration (0x00, 0x399F at
power-on; bit 15 resets every register; BRNG bit 13, 16 V or 32 V; PGA bits 12:11, the
shunt's range ±40 mV × 2^PG; BADC bits 10:7 and SADC bits 6:3, the conversion times;
MODE bits 2:0, 0 power-down, 7 continuous), shunt voltage (0x01: signed, 10 µV a count,
clipped at the PGA's range), bus voltage (0x02: the volts / 4 mV in bits 15:3; bit 1 CNVR,
a conversion is ready since the power register was last read; bit 0 OVF, the current or
power out of range), power (0x03: current × bus / 5000, reading it clears CNVR), current
(0x04: shunt × calibration / 4096, signed; 0 until calibrated), calibration (0x05, bit 0
reads 0). A conversion takes the shunt's and the bus's ADC times (532 µs each at 12 bits;
averaged: up to 68.10 ms); its values are the plant's at the read.

Not modelled: ``NOT_MODELLED`` (docs/parts.md)."""

from sim_plant.buses import BusName, RegisterDevice, check_placement
from sim_plant.catalogue.base import Build, Opt, PartType, View
from sim_plant.option_table import Name, Num

CONFIG, SHUNT, BUS, POWER, CURRENT, CALIBRATION = range(6)
RESET_CONFIG = 0x399F
SHUNT_LSB_V, BUS_LSB_V = 10e-6, 4e-3
ADC_US = {0: 84, 1: 148, 2: 276, 3: 532}  # the ADC's bits (9 to 12): one sample
AVERAGED_US = {9: 1060, 10: 2130, 11: 4260, 12: 8510, 13: 17020, 14: 34050, 15: 68100}  # 2 to 128 samples


def adc_us(setting: int) -> int:
    """A BADC or SADC setting's conversion time (µs)."""
    return ADC_US[setting & 3] if setting < 8 else AVERAGED_US.get(setting, 532)


class Ina219Chip(RegisterDevice):
    FIXED_STATE = (*RegisterDevice.FIXED_STATE, "battery", "shunt_ohm", "bus_v", "idle_a", "motor_a")
    MODELLED = {
        CONFIG: "CONFIGURATION: RST (clears at once: the datasheet's reset is immediate), BRNG, PGA",
        SHUNT: "SHUNT_VOLTAGE",
        BUS: "BUS_VOLTAGE: CNVR (set at each conversion, cleared by reading POWER), OVF",
        POWER: "POWER",
        CURRENT: "CURRENT",
        CALIBRATION: "CALIBRATION",
    }

    def __init__(self, name, bus, address, battery: str, shunt_ohm, bus_v, idle_a, motor_a):
        self.words = {CONFIG: RESET_CONFIG, CALIBRATION: 0}
        super().__init__(name, bus, address)
        self.battery, self.shunt_ohm, self.bus_v = battery, float(shunt_ohm), float(bus_v)
        self.idle_a, self.motor_a = float(idle_a), float(motor_a)
        self.read_at_us = 0  # when the power register was last read (CNVR)
        self.high = 0  # the high byte of a word being written
        self.byte_index = 0
        self.load_a, self.supply = 0.0, self.bus_v  # the plant's, at the transfer's instant

    def power_on(self) -> None:
        super().power_on()
        self.words = {CONFIG: RESET_CONFIG, CALIBRATION: 0}

    def take_in(self, plant) -> None:
        self.load_a, self.supply = self.current_a(plant), self.supply_v(plant)

    # -- what the chip measures -------------------------------------------------------

    def supply_v(self, plant) -> float:
        cell = next((p for p in plant.parts if getattr(p, "label", None) == self.battery), None)
        return float(cell.v) if cell is not None and hasattr(cell, "v") else self.bus_v

    def current_a(self, plant) -> float:
        drive = plant.drive
        motors = getattr(drive, "motors", ())
        shares = [min(1.0, abs(w) / m.max_wheel_rad_s) for w, m in zip(getattr(drive, "wheel_rad_s", ()), motors)]
        return self.idle_a + self.motor_a * sum(shares)

    def conversion_us(self) -> int:
        config = self.words[CONFIG]
        return adc_us(config >> 7 & 0xF) + adc_us(config >> 3 & 0xF)

    def _measure(self, t_us) -> dict:
        config, cal = self.words[CONFIG], self.words[CALIBRATION]
        if config & 7 == 0:  # (powered down: the registers hold)
            return {}
        range_counts = round(0.04 * (1 << (config >> 11 & 3)) / SHUNT_LSB_V)
        shunt = round(self.load_a * self.shunt_ohm / SHUNT_LSB_V)
        overflow = abs(shunt) > range_counts
        shunt = max(-range_counts, min(range_counts, shunt))
        bus = min(0x1FFF, round(self.supply / BUS_LSB_V))
        current = int(shunt * cal / 4096)
        power = abs(current) * bus // 5000
        overflow = (
            overflow or not -0x8000 <= current <= 0x7FFF or power > 0xFFFF or (config & 0x2000 == 0 and bus > 4000)
        )
        ready = t_us - self.read_at_us >= self.conversion_us()
        return {
            SHUNT: shunt & 0xFFFF,
            BUS: bus << 3 | (2 if ready else 0) | int(overflow),
            POWER: min(power, 0xFFFF),
            CURRENT: max(-0x8000, min(0x7FFF, current)) & 0xFFFF,
        }

    # -- the register file: 16-bit words, the high byte first -------------------------

    def begin(self, t_us, reading):
        super().begin(t_us, reading)
        self.byte_index = 0

    def read(self, t_us):
        reg = self.pointer
        word = self._measure(t_us).get(reg, self.words.get(reg, 0)) if reg < 6 else 0
        if reg == CALIBRATION:
            word &= 0xFFFE
        high = self.byte_index % 2 == 0
        self.byte_index += 1
        if not high and reg == POWER:
            self.read_at_us = t_us  # (reading the power register clears CNVR)
        return word >> 8 if high else word & 0xFF

    def write(self, t_us, byte):
        if not self.pointed:
            self.pointer, self.pointed, self.byte_index = byte, True, 0
            return True
        if self.byte_index % 2 == 0:
            self.high = byte
        else:
            self._store_word(t_us, self.pointer, self.high << 8 | byte)
        self.byte_index += 1
        return True

    def _store_word(self, t_us, reg, word) -> None:
        if reg == CONFIG:
            if word & 0x8000:
                self.power_on()
                return
            self.words[CONFIG] = word
            self.read_at_us = t_us  # (a new conversion starts)
        elif reg == CALIBRATION:
            self.words[CALIBRATION] = word & 0xFFFE

    def truth(self, t_us, plant) -> dict:
        return {f"{self.label}_current_a": self.current_a(plant), f"{self.label}_bus_v": self.supply_v(plant)}


class Ina219(PartType):
    CHIP = Ina219Chip  # (its registers: docs/parts.md)
    kind = "ina219"
    MODELLED_FEATURES = (
        "bus voltage from the battery part (or a set value), current from the motors' speeds and an idle draw",
        "shunt, bus, power and current registers with the calibration, PGA and BRNG; conversion times; CNVR "
        "and OVF; reset",
    )
    NOT_MODELLED = (
        "the triggered modes (1 to 6 convert continuously)",
        "averaging's smoothing",
        "the ADC's offset and gain errors",
        "the bus voltage's range limit (BRNG only sets OVF beyond 16 V)",
    )
    doc = "An INA219-class current and bus-voltage monitor on I2C, on the battery's supply with the motors' load."
    OPTIONS = (
        Opt("bus", BusName(), "i2c0", "the bus it is on, as the firmware creates it"),
        Opt("address", Num("", 0, 127, whole=True), 0x40, "its 7-bit I2C address (0x40 to 0x4F by A0, A1)"),
        Opt("battery", Name(), None, "the battery part whose voltage is the bus voltage (unset: bus_v)"),
        Opt("bus_v", Num("volts", 0, 26), 5.0, "the bus voltage without a battery part"),
        Opt("shunt_ohm", Num("ohms", 0.001, 10), 0.1, "the shunt resistor (the breakout boards': 0.1)"),
        Opt("idle_a", Num("amperes", 0, 10), 0.05, "the current with the motors stopped"),
        Opt("motor_a", Num("amperes", 0, 10), 0.3, "each motor's current at full speed (in proportion to its speed)"),
    )
    SIGNALS = ()
    TRUTH = ("{name}_current_a", "{name}_bus_v")
    VIEWS = (View("voltage", "the supply's true voltage (its bus voltage)", truth=TRUTH[1:]),)
    on_bus = True

    def check(self) -> None:
        check_placement(self.options, "the INA219")

    def add(self, build: Build) -> None:
        o = self.options
        build.parts.append(
            Ina219Chip(
                self.name, o["bus"], o["address"], o["battery"], o["shunt_ohm"], o["bus_v"], o["idle_a"], o["motor_a"]
            )
        )
