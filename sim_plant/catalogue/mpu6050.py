"""Part ``mpu6050``: an InvenSense MPU-6050-class 6-axis IMU (the MPU-6xxx register map)
on I2C (address 0x68, 0x69 with AD0 high) or SPI (the MPU-6500/6886/9250 have it;
chip select ``<name>.cs``), fed by the body's motion (:mod:`sim_plant.catalogue.imu`).
``who_am_i`` picks the family member a driver checks for (0x68 MPU-6050, 0x70 MPU-6500,
0x19 MPU-6886, 0x71 MPU-9250).

Modelled registers: SMPLRT_DIV (0x19) and CONFIG's DLPF_CFG (0x1A: 8 kHz with the filter
off, else 1 kHz, divided by 1 + SMPLRT_DIV), GYRO_CONFIG (0x1B: FS_SEL), ACCEL_CONFIG
(0x1C: AFS_SEL), INT_ENABLE (0x38: DATA_RDY_EN drives ``<name>.int``), INT_STATUS (0x3A:
DATA_RDY_INT at the sample rate, cleared by reading INT_STATUS, as INT_PIN_CFG's reset
INT_RD_CLEAR = 0 has it; INT_RD_CLEAR = 1 is not modelled), ACCEL_XOUT_H..GYRO_ZOUT_L (0x3B..0x48, big-endian,
temperature 25 °C by the formula of the member WHO_AM_I says), PWR_MGMT_1 (0x6B: resets
to SLEEP, 0x40; DEVICE_RESET resets the registers and reads set for 100 ms; asleep, no
samples), WHO_AM_I (0x75). Every other register is plain memory (a write to one is named
once in the run's output)."""

from sim_plant.buses import DataReady, SelfClearing
from sim_plant.catalogue.base import Opt
from sim_plant.catalogue.imu import G_M_S2, Imu, ImuPart, counts, put16
from sim_plant.controls import Control
from sim_plant.option_table import Num, OneOf

SMPLRT_DIV, CONFIG, GYRO_CONFIG, ACCEL_CONFIG = 0x19, 0x1A, 0x1B, 0x1C
INT_ENABLE, INT_STATUS = 0x38, 0x3A
ACCEL_XOUT_H, TEMP_OUT_H, GYRO_XOUT_H, OUT_END = 0x3B, 0x41, 0x43, 0x49
PWR_MGMT_1, WHO_AM_I = 0x6B, 0x75
GYRO_LSB_PER_DPS = (131.0, 65.5, 32.8, 16.4)
ACCEL_LSB_PER_G = (16384, 8192, 4096, 2048)
TEMP_25C = {0x68: -3920, 0x19: 0, 0x70: 1336, 0x71: 1336}
"""TEMP_OUT at 25 °C by WHO_AM_I, each member's formula: MPU-6050 (25 - 36.53) * 340;
MPU-6886 (25 - 25) * 326.8; MPU-6500 and MPU-9250 (25 - 21) * 333.87."""
TEMP_FORMULA = {0x68: (36.53, 340.0), 0x19: (25.0, 326.8), 0x70: (21.0, 333.87), 0x71: (21.0, 333.87)}
"""(offset °C, counts per °C) by WHO_AM_I: TEMP_OUT = (T - offset) * counts, the formulas above."""
ACCEL_CONTROLS = ("accelX", "accelY", "accelZ")  # in g, as Wokwi's
GYRO_CONTROLS = ("rotationX", "rotationY", "rotationZ")  # in deg/s


class Mpu6050Chip(Imu):
    RESET = {PWR_MGMT_1: 0x40, WHO_AM_I: 0x68}
    MODELLED = {
        SMPLRT_DIV: "SMPLRT_DIV (the sample rate)",
        CONFIG: "CONFIG: DLPF_CFG (the base rate)",
        GYRO_CONFIG: "GYRO_CONFIG: FS_SEL",
        ACCEL_CONFIG: "ACCEL_CONFIG: AFS_SEL",
        INT_ENABLE: "INT_ENABLE: DATA_RDY_EN (the int line)",
        INT_STATUS: "INT_STATUS: DATA_RDY_INT at the sample rate, cleared by reading INT_STATUS",
        **{reg: "ACCEL_XOUT..GYRO_ZOUT, TEMP_OUT" for reg in range(ACCEL_XOUT_H, OUT_END)},
        PWR_MGMT_1: "PWR_MGMT_1: DEVICE_RESET (100 ms), SLEEP",
        WHO_AM_I: "WHO_AM_I: as the who_am_i option",
    }
    SELF_CLEARING = (
        # MPU-6000/MPU-6050 Register Map (RM-MPU-6000A) 4.28 PWR_MGMT_1: DEVICE_RESET resets
        # every register to its default and "automatically clears to 0 once the reset is
        # done"; its reset sequence waits 100 ms for it.
        SelfClearing(PWR_MGMT_1, 0x80, 100_000, "DEVICE_RESET", resets=True, source="RM-MPU-6000A 4.28"),
    )

    DATA_READY = (
        # RM-MPU-6000A 4.17 INT_STATUS: DATA_RDY_INT is set when a write to the sensor
        # registers completes (each sample) and, with INT_PIN_CFG's INT_RD_CLEAR at its reset
        # 0 (4.15), cleared only by reading INT_STATUS.
        DataReady(INT_STATUS, 0x01, (INT_STATUS,), "DATA_RDY_INT", source="RM-MPU-6000A 4.15, 4.17"),
    )

    def power_on(self) -> None:
        super().power_on()
        self.regs[WHO_AM_I] = getattr(self, "who_am_i", 0x68)

    def period_us(self) -> int:
        if self.regs[PWR_MGMT_1] & 0x40:
            return 0
        base_hz = 8000 if self.regs[CONFIG] & 0x07 in (0, 7) else 1000
        return round(1e6 * (1 + self.regs[SMPLRT_DIV]) / base_hz)

    def drdy_enabled(self) -> bool:
        return bool(self.regs[INT_ENABLE] & 0x01)

    def load(self, t_us, reg):
        if reg == INT_STATUS:
            self.taken(t_us)  # (the data-ready line falls)
            return 0x00  # (DATA_RDY_INT: DATA_READY)
        if ACCEL_XOUT_H <= reg < OUT_END:
            self._fill(t_us)
            self.taken(t_us)
        return self.regs[reg]

    def _controlled(self, t_us: int, sample: tuple) -> tuple:
        """The sample with each axis a scenario's set-control set replaced (g and deg/s
        to m/s² and deg/s); the temperature in °C (25 unless set)."""
        controls = getattr(self, "controls", None)
        if controls is None or not controls.entries:
            return sample, 25.0
        gyro = [controls.value_at(self.label, c, t_us, v) for c, v in zip(GYRO_CONTROLS, sample[:3])]
        accel = [
            sample[3 + i] if g is None else g * G_M_S2
            for i, g in enumerate(controls.value_at(self.label, c, t_us) for c in ACCEL_CONTROLS)
        ]
        return (*gyro, *accel), controls.value_at(self.label, "temperature", t_us, 25.0)

    def _fill(self, t_us: int) -> None:
        (gx, gy, gz, ax, ay, az), temp_c = self._controlled(t_us, self.current(t_us))
        regs = self.regs
        per_dps = 1 / GYRO_LSB_PER_DPS[regs[GYRO_CONFIG] >> 3 & 3]
        per_m_s2 = G_M_S2 / ACCEL_LSB_PER_G[regs[ACCEL_CONFIG] >> 3 & 3]
        for i, value in enumerate((ax, ay, az)):
            put16(regs, ACCEL_XOUT_H + 2 * i, counts(value, per_m_s2), True)
        offset_c, per_c = TEMP_FORMULA[regs[WHO_AM_I]]
        temp = TEMP_25C[regs[WHO_AM_I]] if temp_c == 25.0 else counts((temp_c - offset_c) * per_c, 1)
        put16(regs, TEMP_OUT_H, temp, True)
        for i, value in enumerate((gx, gy, gz)):
            put16(regs, GYRO_XOUT_H + 2 * i, counts(value, per_dps), True)

    def store(self, t_us, reg, value):
        if reg == WHO_AM_I or ACCEL_XOUT_H <= reg < OUT_END or reg == INT_STATUS:
            return  # read-only
        self.regs[reg] = value & 0xFF
        self.rearm(t_us)


class Mpu6050(ImuPart):
    kind = "mpu6050"
    MODELLED_FEATURES = (
        "gyro: the body's turn rate about z, with the bias and noise set, saturated at the full scale",
        "accelerometer: the forward and centripetal acceleration on x and y, +g on z (flat, face up), with noise",
        "a sample a tick of the output data rate (a read between two ticks gets the same sample)",
        "the data-ready line (int) as the interrupt enable register routes it",
        "I2C at 0x68/0x69 or SPI; WHO_AM_I of the member chosen (MPU-6050, 6500, 6886, 9250) and its "
        "temperature formula",
    )
    NOT_MODELLED = (
        "the FIFO",
        "the DMP (digital motion processor)",
        "the auxiliary I2C master (the MPU-9250's magnetometer)",
        "INT_PIN_CFG's INT_RD_CLEAR = 1 (any read clears), latch and level options",
        "the DLPF's filtering of the samples (only its rate)",
        "self-test",
        "the temperature sensor (a set 25 °C)",
        "cycle and low-power modes",
    )
    doc = "An MPU-6050-class 6-axis IMU (MPU-6xxx registers, WHO_AM_I as chosen) on I2C or SPI, from the body's motion."
    CHIP = Mpu6050Chip
    OPTIONS = (
        *ImuPart.bus_options(0x68),
        Opt(
            "who_am_i",
            OneOf((0x68, 0x70, 0x19, 0x71)),
            0x68,
            "what WHO_AM_I reads (the family member a driver expects)",
        ),
    )

    CONTROLS = (
        *(
            Control(n, Num("g", -16, 16), f"the {n[-1]} acceleration in g (replaces the motion's)")
            for n in ACCEL_CONTROLS
        ),
        *(Control(n, Num("deg/s", -2000, 2000), f"the {n[-1]} turn rate in deg/s") for n in GYRO_CONTROLS),
        Control("temperature", Num("°C", -40, 85), "the die temperature"),
    )

    def engine(self, build):
        device = super().engine(build)
        device.controls = build.controls
        device.who_am_i = self.options["who_am_i"]
        device.power_on()
        return device
