"""Part ``lsm6dsox``: an ST LSM6DSOX-class 6-axis IMU (LSM6DS family registers) on I2C
(address 0x6A, 0x6B with SA0 high) or SPI (chip select ``<name>.cs``), fed by the
body's motion (:mod:`sim_plant.catalogue.imu`).

``who_am_i`` picks the family member a driver checks for: 0x6C (LSM6DSOX, LSM6DSO), 0x6A
(LSM6DSL), 0x69 (LSM6DS3, LSM6DS33); the registers below are the LSM6DSOX's for each.

Modelled registers: WHO_AM_I (0x0F, as ``who_am_i``), INT1_CTRL (0x0D: INT1_DRDY_XL/G drive
``<name>.int``), CTRL1_XL (0x10: ODR_XL, FS_XL), CTRL2_G (0x11: ODR_G, FS_G, FS_125),
CTRL3_C (0x12: SW_RESET resets the registers and reads set for 50 µs, BOOT reads set for
10 ms and leaves the registers as they are, IF_INC), STATUS_REG
(0x1E: XLDA at the accelerometer's rate, cleared by reading its outputs; GDA at the gyro's,
cleared by reading its outputs; TDA not modelled), OUT_TEMP (0x20, 25 °C), OUTX_L_G..OUTZ_H_G (0x22), OUTX_L_A..OUTZ_H_A
(0x28), little-endian. Every other register is plain memory (a write to one is named once
in the run's output). One output data rate: the
gyro's (the accelerometer's while the gyro is powered down)."""

import struct

from sim_plant.buses import DataReady, SelfClearing
from sim_plant.catalogue.base import Opt
from sim_plant.catalogue.imu import G_M_S2, Imu, ImuPart
from sim_plant.option_table import OneOf

WHO_AM_I = 0x0F
INT1_CTRL = 0x0D
CTRL1_XL, CTRL2_G, CTRL3_C = 0x10, 0x11, 0x12
STATUS_REG = 0x1E
OUT_TEMP_L, OUTX_L_G, OUTX_L_A, OUT_END = 0x20, 0x22, 0x28, 0x2E
ODR_HZ = {1: 12.5, 2: 26, 3: 52, 4: 104, 5: 208, 6: 416, 7: 833, 8: 1666, 9: 3332, 10: 6664, 11: 1.6}
ODR_US = {code: round(1e6 / hz) for code, hz in ODR_HZ.items()}  # (the period of each ODR code, in us)
GYRO_MDPS = {0: 8.75, 1: 17.5, 2: 35.0, 3: 70.0}  # per count, by FS_G
ACCEL_MG = {0: 0.061, 1: 0.488, 2: 0.122, 3: 0.244}  # per count, by FS_XL (2, 16, 4, 8 g)
_OUTPUTS = struct.Struct("<7h").pack  # OUT_TEMP_L..OUT_END: seven 16-bit counts, little-endian


class Lsm6dsoxChip(Imu):
    RESET = {WHO_AM_I: 0x6C, CTRL3_C: 0x04}
    MODELLED = {
        INT1_CTRL: "INT1_CTRL: INT1_DRDY_XL, INT1_DRDY_G (the int line)",
        WHO_AM_I: "WHO_AM_I: as the who_am_i option (0x6C)",
        CTRL1_XL: "CTRL1_XL: ODR_XL, FS_XL",
        CTRL2_G: "CTRL2_G: ODR_G, FS_G, FS_125",
        CTRL3_C: "CTRL3_C: BOOT (10 ms), SW_RESET (50 us), IF_INC",
        STATUS_REG: "STATUS_REG: XLDA, GDA at each sensor's output data rate, cleared by reading its outputs",
        **{reg: "OUT_TEMP, OUTX..OUTZ_G, OUTX..OUTZ_A" for reg in range(OUT_TEMP_L, OUT_END)},
    }
    SELF_CLEARING = (
        # LSM6DSOX datasheet, 9.14 CTRL3_C: BOOT "automatically cleared" after the reboot of the
        # trimming memory; AN5272 (LSM6DSOX), "Reboot and software reset": the boot takes 10 ms
        # and leaves the control registers as they are; SW_RESET resets them and takes 50 us.
        SelfClearing(CTRL3_C, 0x80, 10_000, "BOOT", source="LSM6DSOX datasheet 9.14; AN5272 5.7"),
        SelfClearing(CTRL3_C, 0x01, 50, "SW_RESET", resets=True, source="LSM6DSOX datasheet 9.14; AN5272 5.7"),
    )

    DATA_READY = (
        # LSM6DSOX datasheet 9.26 STATUS_REG: XLDA / GDA, new data available, cleared when the
        # sensor's output registers are read (AN5272, "Reading output data").
        DataReady(STATUS_REG, 0x01, tuple(range(OUTX_L_A, OUT_END)), "XLDA", "accel_period_us", source="9.26"),
        DataReady(STATUS_REG, 0x02, tuple(range(OUTX_L_G, OUTX_L_A)), "GDA", "gyro_period_us", source="9.26"),
    )

    def power_on(self) -> None:
        super().power_on()
        self.regs[WHO_AM_I] = getattr(self, "who_am_i", 0x6C)

    def period_us(self) -> int:
        """The samples' rate: the gyro's (the accelerometer's while the gyro is powered down)."""
        return self.gyro_period_us() or self.accel_period_us()

    def gyro_period_us(self) -> int:
        return ODR_US.get(self.regs[CTRL2_G] >> 4, 0)

    def accel_period_us(self) -> int:
        return ODR_US.get(self.regs[CTRL1_XL] >> 4, 0)

    def drdy_enabled(self) -> bool:
        return bool(self.regs[INT1_CTRL] & 0x03)

    def next_register(self, reg: int) -> int:
        return (reg + 1) & 0xFF if self.regs[CTRL3_C] & 0x04 else reg

    def read_block(self, t_us: int, n: int) -> bytes:
        """``n`` bytes read on from the pointer: the output registers' (with IF_INC) at once,
        the sample filled once, as byte by byte (:meth:`read`) would read them."""
        p = self.pointer
        if n < 2 or p < OUT_TEMP_L or p + n > OUT_END or not self.regs[CTRL3_C] & 0x04:
            return super().read_block(t_us, n)
        if self.clearing:
            self._settle(t_us)
        self._fill(t_us)
        if p + n > OUTX_L_G:
            self.taken(t_us)
        for bit in self.DATA_READY:
            if p < bit.cleared_by[-1] + 1 and bit.cleared_by[0] < p + n:
                period = getattr(self, bit.period)()
                self.read_ticks[bit.name] = t_us // period if period else -1
        self.pointer = p + n
        return bytes(self.regs[p : p + n])

    def load(self, t_us, reg):
        if OUT_TEMP_L <= reg < OUT_END:
            self._fill(t_us)
            if reg >= OUTX_L_G:
                self.taken(t_us)
        return self.regs[reg]

    # The sample, CTRL2_G and CTRL1_XL the output registers were last filled from, and what
    # they then held: a read of the next byte of the same sample finds them so and fills
    # nothing (a 12-byte read filled them once, not 12 times; class defaults: a snapshot
    # taken before the first fill restores these, so the next read fills again).
    filled_from = None
    filled = ()

    def _fill(self, t_us: int) -> None:
        sample = self.current(t_us)
        regs = self.regs
        key = (sample, regs[CTRL2_G], regs[CTRL1_XL])
        if key == self.filled_from and tuple(regs[OUT_TEMP_L:OUT_END]) == self.filled:
            return
        gx, gy, gz, ax, ay, az = sample
        gyro_dps = GYRO_MDPS[regs[CTRL2_G] >> 2 & 3] / 1000 if not regs[CTRL2_G] & 0x02 else 0.004375
        accel_m_s2 = ACCEL_MG[regs[CTRL1_XL] >> 2 & 3] / 1000 * G_M_S2
        # OUT_TEMP (0: 25 °C), then the gyro's and the accelerometer's counts, each little-endian
        # (imu.counts inline: each saturated at the register's ends)
        out = _OUTPUTS(
            0,
            max(-32768, min(32767, round(gx / gyro_dps))),
            max(-32768, min(32767, round(gy / gyro_dps))),
            max(-32768, min(32767, round(gz / gyro_dps))),
            max(-32768, min(32767, round(ax / accel_m_s2))),
            max(-32768, min(32767, round(ay / accel_m_s2))),
            max(-32768, min(32767, round(az / accel_m_s2))),
        )
        regs[OUT_TEMP_L:OUT_END] = out
        self.filled_from, self.filled = key, tuple(out)

    def store(self, t_us, reg, value):
        if reg == WHO_AM_I or OUT_TEMP_L <= reg < OUT_END or reg == STATUS_REG:
            return  # read-only
        self.regs[reg] = value & 0xFF
        self.rearm(t_us)


WHO_AM_I_OPTION = Opt(
    "who_am_i",
    OneOf((0x6C, 0x6A, 0x69)),
    0x6C,
    "what WHO_AM_I reads (the family member a driver expects: 0x6C LSM6DSOX/LSM6DSO, 0x6A LSM6DSL, "
    "0x69 LSM6DS3/LSM6DS33)",
)


class Lsm6dsox(ImuPart):
    kind = "lsm6dsox"
    MODELLED_FEATURES = (
        "gyro: the body's turn rate about z, with the bias and noise set, saturated at the full scale",
        "accelerometer: the forward and centripetal acceleration on x and y, +g on z (flat, face up), with noise",
        "a sample a tick of the output data rate (a read between two ticks gets the same sample)",
        "the data-ready line (int) as the interrupt enable register routes it",
        "I2C at 0x6A/0x6B or SPI, the register pointer moving on as IF_INC says",
    )
    NOT_MODELLED = (
        "the FIFO (its registers are plain memory)",
        "the embedded functions (pedometer, tilt, tap, free-fall, 6D, the machine-learning core, the finite "
        "state machine)",
        "INT2 and the routing of anything but data-ready",
        "the sensor hub and OIS interfaces",
        "self-test",
        "the temperature sensor (OUT_TEMP reads 25 °C; TDA never sets)",
        "the accelerometer's and gyro's own output data rates apart (one rate: the gyro's, the "
        "accelerometer's while it is off)",
        "the low-power modes' noise",
        "the LSM6DSL's and LSM6DS3's own differences from the LSM6DSOX (who_am_i 0x6A, 0x69: their identity only)",
        "the filters' (LPF, HPF) effect on the samples",
    )
    doc = "An LSM6DSOX-class 6-axis IMU (WHO_AM_I 0x6C) on I2C or SPI: gyro and accelerometer from the body's motion."
    CHIP = Lsm6dsoxChip
    OPTIONS = (*ImuPart.bus_options(0x6A), WHO_AM_I_OPTION)

    def engine(self, build):
        device = super().engine(build)
        device.who_am_i = self.options["who_am_i"]
        device.power_on()
        return device
