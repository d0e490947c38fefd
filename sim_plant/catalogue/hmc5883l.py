"""Part ``hmc5883l``: a Honeywell HMC5883L 3-axis magnetometer on I2C (address 0x1E), giving
the body's heading from the Earth's field plus a hard-iron offset and noise, as the
``lis3mdl`` part computes it (its options and field).

Modelled registers (HMC5883L datasheet): configuration A 0x00 (DO: the output data rate,
0.75 to 75 Hz, reset 15 Hz; MA and MS kept, not modelled), configuration B 0x01 (GN: 1370,
1090, 820, 660, 440, 390, 330 or 230 LSB per gauss, reset 1090), mode 0x02 (MD: continuous,
single, idle; reset single: the chip waits in idle until told; a single measurement is
ready 6 ms after the write, then the mode reads idle, 0b11), data 0x03..0x08 (X, Z, Y,
MSB first, -2048..2047, -4096 in an axis that overflows the range), status 0x09 (RDY: set
once a measurement has written the data, clear for 250 us as each new one is written;
LOCK not modelled: reading part of the data does not hold it), identification 0x0A..0x0C
('H', '4', '3'). The pointer moves on after each byte, from 0x08 back to 0x03 and from
0x0C to 0x00. Not modelled: ``NOT_MODELLED`` (docs/parts.md).
A write to another register is named once in the run's output."""

from sim_plant.buses import RegisterDevice
from sim_plant.catalogue.lis3mdl import Lis3mdl, Lis3mdlChip

CRA, CRB, MODE, DATA, STATUS, IDENT = 0x00, 0x01, 0x02, 0x03, 0x09, 0x0A
DATA_END = 0x09
DO_HZ = (0.75, 1.5, 3, 7.5, 15, 30, 75)
LSB_PER_GAUSS = (1370, 1090, 820, 660, 440, 390, 330, 230)
UT_PER_GAUSS = 100.0
SINGLE_US = 6_000  # the datasheet's single measurement: 6 ms
RDY_CLEAR_US = 250  # RDY clear as new data is written


class Hmc5883lChip(Lis3mdlChip):
    READS_STEADY = False  # RDY clears for 250 us after each sample, inside a tick (busimage)

    RESET = {CRA: 0x10, CRB: 0x20, MODE: 0x01, IDENT: 0x48, IDENT + 1: 0x34, IDENT + 2: 0x33}
    MODELLED = {
        CRA: "configuration A: DO (MA, MS kept)",
        CRB: "configuration B: GN",
        MODE: "mode: MD (continuous, single 6 ms then idle, idle)",
        **{reg: "data X, Z, Y (MSB first; -4096 on overflow)" for reg in range(DATA, DATA_END)},
        STATUS: "status: RDY (LOCK not modelled)",
        **{reg: "identification: 'H', '4', '3'" for reg in range(IDENT, IDENT + 3)},
    }
    SELF_CLEARING = ()
    DATA_READY = ()
    FIXED_STATE = (*Lis3mdlChip.FIXED_STATE, "started_us", "single_us")

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.started_us = None  # when continuous mode began
        self.single_us = None  # when the single measurement asked for is written
        self.written_us = None  # when the data was last written

    def period_us(self) -> int:
        if self.regs[MODE] & 0x03 != 0x00:
            return 0  # single (its own time) or idle
        hz = DO_HZ[min(self.regs[CRA] >> 2 & 7, 6)]
        return round(1e6 / hz)

    def _last_written(self, t_us: int):
        """When a measurement last wrote the data registers at ``t_us`` (None: never)."""
        if self.single_us is not None and t_us >= self.single_us:
            self.sample = self._measure(self.single_us)
            self.written_us, self.single_us = self.single_us, None
            self.regs[MODE] = self.regs[MODE] & 0xFC | 0x03  # idle once done
        period = self.period_us()
        if period and self.started_us is not None:
            tick = t_us // period * period
            if tick > self.started_us:
                self.current(t_us)
                self.written_us = tick
        return self.written_us

    def load(self, t_us, reg):
        written = self._last_written(t_us)
        if DATA <= reg < DATA_END:
            per_ut = UT_PER_GAUSS / LSB_PER_GAUSS[self.regs[CRB] >> 5]
            x, y, z = (round(v / per_ut) for v in self.sample)
            for i, value in enumerate((x, z, y)):
                value = value if -2048 <= value <= 2047 else -4096
                self.regs[DATA + 2 * i], self.regs[DATA + 2 * i + 1] = value >> 8 & 0xFF, value & 0xFF
        elif reg == STATUS:
            return 1 if written is not None and t_us - written >= RDY_CLEAR_US else 0
        return self.regs[reg]

    def write(self, t_us, byte):
        return RegisterDevice.write(self, t_us, byte)

    def next_register(self, reg: int) -> int:
        if reg == DATA_END - 1:
            return DATA
        return 0 if reg >= IDENT + 2 else reg + 1

    def store(self, t_us, reg, value):
        if DATA <= reg <= IDENT + 2:
            return  # read-only
        self._last_written(t_us)
        self.regs[reg] = value & 0xFF
        if reg == MODE:
            md = value & 0x03
            self.started_us = t_us if md == 0 else None
            self.single_us = t_us + SINGLE_US if md == 1 else None


class Hmc5883l(Lis3mdl):
    CHIP = Hmc5883lChip  # (its registers: docs/parts.md)
    kind = "hmc5883l"
    MODELLED_FEATURES = (
        "the field as the lis3mdl part computes it (hard iron, noise), the eight gains, overflow",
        "continuous, single (ready 6 ms after the write, then idle) and idle modes at 0.75 to 75 Hz; RDY",
    )
    NOT_MODELLED = (
        "self-test (MS)",
        "averaging (MA: kept)",
        "the DRDY pin",
        "high-speed I2C",
        "the status register's LOCK",
    )
    doc = "An HMC5883L 3-axis magnetometer (identity 'H43') on I2C at 0x1E: the body's heading, a hard-iron offset."
    OPTIONS = Lis3mdl.options_at(0x1E, "its 7-bit I2C address (0x1E)")  # (check and add: the LIS3MDL's, with this chip)
