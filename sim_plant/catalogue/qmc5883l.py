"""Part ``qmc5883l``: a QST QMC5883L 3-axis magnetometer on I2C (address 0x0D), the
compass of many "HMC5883L" boards, giving the body's heading from the Earth's field plus a
hard-iron offset and noise, as the ``lis3mdl`` part computes it (its options and field).

Modelled registers (QMC5883L datasheet, 9.2): the data 0x00..0x05 (X, Y, Z, LSB first,
saturated; 12000 LSB per gauss at RNG 2 G, 3000 at 8 G), the status 0x06 (DRDY: a sample not
yet read, set at the output data rate; DOR: a sample skipped, the next one arrived before
the data was read, counted from the start of continuous mode; OVL: an axis out of range;
DRDY and DOR clear when a data register is read), TOUT 0x07..0x08 (0: the datasheet's
temperature is relative, uncalibrated), control 1 0x09 (MODE: standby or continuous, ODR
10/50/100/200 Hz, RNG; OSR kept, not modelled), control 2 0x0A (SOFT_RST resets the
registers and reads set until the power-on time, 350 us, has passed; ROL_PNT: the pointer
rolls over from 0x06 to 0x00; INT_ENB kept, no interrupt pin), SET/RESET period 0x0B
(kept), chip id 0x0D (reads 0xFF). The register pointer moves on after each byte. Not
modelled: the OSR's noise, the interrupt pin. A write to another register is named once
in the run's output."""

from sim_plant.buses import DataReady, RegisterDevice, SelfClearing
from sim_plant.catalogue.imu import counts, put16
from sim_plant.catalogue.lis3mdl import Lis3mdl, Lis3mdlChip

DATA, STATUS, TOUT, CONTROL1, CONTROL2, SET_RESET, CHIP_ID = 0x00, 0x06, 0x07, 0x09, 0x0A, 0x0B, 0x0D
DRDY, OVL, DOR = 0x01, 0x02, 0x04
ODR_HZ = (10, 50, 100, 200)
LSB_PER_GAUSS = (12000, 3000)  # by RNG (control 1 bits 5:4): 2 G, 8 G
UT_PER_GAUSS = 100.0


class Qmc5883lChip(Lis3mdlChip):
    RESET = {CHIP_ID: 0xFF}
    MODELLED = {
        **{reg: "DATA X, Y, Z (LSB first)" for reg in range(DATA, STATUS)},
        STATUS: "STATUS: DRDY, OVL, DOR",
        TOUT: "TOUT (0)",
        TOUT + 1: "TOUT (0)",
        CONTROL1: "CONTROL 1: MODE, ODR, RNG (OSR kept)",
        CONTROL2: "CONTROL 2: SOFT_RST (350 us), ROL_PNT (INT_ENB kept)",
        SET_RESET: "SET/RESET period (kept)",
        CHIP_ID: "chip id: 0xFF",
    }
    SELF_CLEARING = (
        # QMC5883L datasheet 9.2.4 control register 2: SOFT_RST "restore default value of
        # all registers"; 8.1 the power-on (POR) completion time: 350 us.
        SelfClearing(CONTROL2, 0x80, 350, "SOFT_RST", resets=True, source="QMC5883L datasheet 9.2.4, 8.1"),
    )
    DATA_READY = (
        # QMC5883L datasheet 9.2.2 status register: DRDY set when all three axes are loaded
        # in continuous mode, reset by reading any data register (DOR: the chip's load()).
        DataReady(STATUS, DRDY, tuple(range(DATA, STATUS)), "DRDY", source="QMC5883L datasheet 9.2.2"),
    )
    FIXED_STATE = (*Lis3mdlChip.FIXED_STATE, "started_tick")

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.started_tick = -1  # the output data rate's tick continuous mode began in

    def period_us(self) -> int:
        control = self.regs[CONTROL1]
        if control & 0x03 != 0x01:
            return 0  # standby
        return round(1e6 / ODR_HZ[control >> 2 & 3])

    def _counts(self, t_us) -> tuple:
        per_ut = UT_PER_GAUSS / LSB_PER_GAUSS[self.regs[CONTROL1] >> 4 & 1]
        return tuple(counts(value, per_ut) for value in self.current(t_us))

    def load(self, t_us, reg):
        if DATA <= reg < STATUS:
            for i, value in enumerate(self._counts(t_us)):
                put16(self.regs, DATA + 2 * i, value, False)
        elif reg == STATUS:
            period = self.period_us()
            value = 0
            if period:
                read = self.read_ticks.get("DRDY", -1)
                value |= DOR if t_us // period - max(read, self.started_tick) >= 2 else 0
                value |= OVL if any(abs(c) >= 32767 for c in self._counts(t_us)) else 0
            return value
        return self.regs[reg]

    def write(self, t_us, byte):
        return RegisterDevice.write(self, t_us, byte)

    def next_register(self, reg: int) -> int:
        if reg == STATUS and self.regs[CONTROL2] & 0x40:
            return DATA  # ROL_PNT
        return (reg + 1) & 0xFF

    def store(self, t_us, reg, value):
        if reg == CHIP_ID or DATA <= reg <= TOUT + 1:
            return  # read-only
        was = self.period_us()
        self.regs[reg] = value & 0xFF
        period = self.period_us()
        if period and period != was:
            self.started_tick = t_us // period
            self.read_ticks.pop("DRDY", None)


class Qmc5883l(Lis3mdl):
    CHIP = Qmc5883lChip  # (its registers: docs/parts.md)
    kind = "qmc5883l"
    MODELLED_FEATURES = (
        "the field as the lis3mdl part computes it (hard iron, noise), 12000 or 3000 LSB per gauss",
        "standby and continuous modes at 10, 50, 100 or 200 Hz; DRDY, DOR, OVL; SOFT_RST; ROL_PNT",
    )
    NOT_MODELLED = (
        "the oversampling ratio's effect on noise (OSR is kept)",
        "the interrupt pin (INT_ENB is kept)",
        "the temperature sensor (TOUT reads 0)",
    )
    doc = "A QMC5883L 3-axis magnetometer (chip id 0xFF) on I2C at 0x0D: the body's heading, a hard-iron offset."
    OPTIONS = Lis3mdl.options_at(0x0D, "its 7-bit I2C address (0x0D)")  # (check and add: the LIS3MDL's, with this chip)
