"""Part ``lis3mdl``: an ST LIS3MDL-class 3-axis magnetometer on I2C (address 0x1C, 0x1E with
SDO high) giving the body's heading from the Earth's field, plus a hard-iron offset (the
robot's own magnets and steel, turning with it) and noise.

The field: ``horizontal_ut`` towards magnetic north, which lies ``north_deg`` from the
world's x axis (counter-clockwise; 90: north is +y), and ``vertical_ut`` downwards. The
chip lies flat, face up, its x axis along the mount's heading, y to its left: at a
heading of ``theta`` its x reads ``H cos(north - theta - mount)``, y ``H sin(...)``, z
``-V``, each plus ``hard_iron_ut`` and Gaussian noise, so ``atan2(y, x)`` of a calibrated
reading is the compass heading (clockwise from north).

Modelled registers: WHO_AM_I (0x0F, reads 0x3D), CTRL_REG1 (0x20: DO and FAST_ODR set the
output data rate, reset 10 Hz), CTRL_REG2 (0x21: FS, ±4/8/12/16 gauss at 6842/3421/2281/
1711 LSB per gauss; SOFT_RST resets the registers, REBOOT reloads the trimming memory and
leaves them; each reads set until it is done, then clear), CTRL_REG3 (0x22: MD, resets to 0b11
power-down: no new samples), STATUS_REG (0x27: XDA, YDA, ZDA, a sample of that axis not yet
read, ZYXDA of any; XOR, YOR, ZOR, ZYXOR, one overwritten before it was read; each
clears when its axis' outputs (ZYXDA, ZYXOR: any output) are read),
OUT_X_L..OUT_Z_H (0x28..0x2D, little-endian, saturated), TEMP_OUT (0x2E, 25 °C: 0). The
register pointer moves on after each byte whether or not the sub-address has bit 7 set
(the datasheet asks for it; the published drivers read without it). Not modelled: ``NOT_MODELLED`` (docs/parts.md).
A write to a register not modelled is named once in the run's output."""

import math

from sim_plant.buses import BusName, DataReady, RegisterDevice, SelfClearing, check_placement
from sim_plant.catalogue.base import Build, Opt, PartType, View
from sim_plant.catalogue.imu import counts, put16
from sim_plant.option_table import Num, Row

WHO_AM_I, CTRL_REG1, CTRL_REG2, CTRL_REG3, STATUS_REG = 0x0F, 0x20, 0x21, 0x22, 0x27
OUT_X_L, TEMP_OUT_L, OUT_END = 0x28, 0x2E, 0x30
LSB_PER_GAUSS = (6842, 3421, 2281, 1711)
UT_PER_GAUSS = 100.0
DO_HZ = (0.625, 1.25, 2.5, 5, 10, 20, 40, 80)
FAST_HZ = (1000, 560, 300, 155)  # by OM (CTRL_REG1 bits 6:5) with FAST_ODR
HISTORY = 16


class Lis3mdlChip(RegisterDevice):
    READS_STEADY = True  # its reads change only at its output data rate's ticks (busimage)

    RESET = {WHO_AM_I: 0x3D, CTRL_REG1: 0x10, CTRL_REG3: 0x03}
    MODELLED = {
        WHO_AM_I: "WHO_AM_I: 0x3D",
        CTRL_REG1: "CTRL_REG1: DO, FAST_ODR, OM (the output data rate)",
        CTRL_REG2: "CTRL_REG2: FS, REBOOT (5 ms), SOFT_RST (50 us)",
        CTRL_REG3: "CTRL_REG3: MD (power-down: no samples)",
        0x23: "CTRL_REG4 (plain: OMZ, BLE not modelled)",
        0x24: "CTRL_REG5 (plain: BDU not modelled)",
        STATUS_REG: "STATUS_REG: XDA..ZYXDA, XOR..ZYXOR at the output data rate, cleared by reading the outputs",
        **{reg: "OUT_X..OUT_Z, TEMP_OUT" for reg in range(OUT_X_L, OUT_END)},
    }
    SELF_CLEARING = (
        # LIS3MDL datasheet (DocID024204), 7.2 CTRL_REG2: REBOOT reboots the memory content
        # (the trimming: the registers keep their values), SOFT_RST resets the configuration
        # and user registers; the chip clears each bit when done. The datasheet gives no
        # duration: ST's own answers for the family give 5 ms (a LIS2DH12 BOOT) to 10 ms (a
        # LIS2MDL reset), so REBOOT takes 5 ms here and SOFT_RST the LSM6DS family's 50 us.
        SelfClearing(CTRL_REG2, 0x08, 5_000, "REBOOT", source="LIS3MDL datasheet 7.2"),
        SelfClearing(CTRL_REG2, 0x04, 50, "SOFT_RST", resets=True, source="LIS3MDL datasheet 7.2"),
    )
    FIXED_STATE = (*RegisterDevice.FIXED_STATE, "field", "hard_iron_ut", "noise_ut", "mount_rad")

    DATA_READY = (
        # LIS3MDL datasheet 7.8 STATUS_REG (every bit below): per axis, new data (bits 0..2) and overrun
        # (bits 4..6); ZYXDA (3) and ZYXOR (7) for any axis.
        *(
            DataReady(STATUS_REG, 1 << i, (OUT_X_L + 2 * i, OUT_X_L + 2 * i + 1), axis + "DA", overrun_mask=0x10 << i)
            for i, axis in enumerate("XYZ")
        ),
        DataReady(STATUS_REG, 0x08, tuple(range(OUT_X_L, TEMP_OUT_L)), "ZYXDA", overrun_mask=0x80, source="7.8"),
    )

    def __init__(self, name, bus, address, *, mount_rad, field, hard_iron_ut, noise_ut, rng):
        super().__init__(name, bus, address)
        self.mount_rad = mount_rad
        self.field = field  # (horizontal_ut, vertical_ut, north_rad)
        self.hard_iron_ut = tuple(float(v) for v in hard_iron_ut)
        self.noise_ut = float(noise_ut)
        self.rng = rng
        self.history = [(0, 0.0, 0.0)]  # (t_us, theta_rad then, w_rad_s from then on)
        self.sample_no = -1
        self.sample = (0.0, 0.0, 0.0)

    def start(self, t_us, plant) -> None:
        self.on_motion_change(t_us, plant)

    def on_motion_change(self, t_us, plant) -> None:
        body = plant.drive.body
        self.history.append((t_us, float(body.pose_at(t_us)[2]), float(body.w)))
        del self.history[:-HISTORY]

    def heading_at(self, t_us: int) -> float:
        """The body's heading (world, rad) at ``t_us``, from the motion's history."""
        for t0, theta, w in reversed(self.history):
            if t0 <= t_us:
                return theta + w * (t_us - t0) * 1e-6
        return self.history[0][1]

    def period_us(self) -> int:
        if self.regs[CTRL_REG3] & 0x02:
            return 0  # power-down
        reg1 = self.regs[CTRL_REG1]
        hz = FAST_HZ[reg1 >> 5 & 3] if reg1 & 0x02 else DO_HZ[reg1 >> 2 & 7]
        return round(1e6 / hz)

    def current(self, t_us: int) -> tuple:
        period = self.period_us()
        if period and t_us // period != self.sample_no:
            self.sample_no = t_us // period
            self.sample = self._measure(self.sample_no * period)
        return self.sample

    def _measure(self, t_us: int) -> tuple:
        horizontal, vertical, north = self.field
        angle = north - self.heading_at(t_us) - self.mount_rad[2]
        true = (horizontal * math.cos(angle), horizontal * math.sin(angle), -vertical)
        noise = self.rng.standard_normal(3).tolist()  # (Python floats: the same values, cheaper arithmetic)
        return tuple(true[i] + self.hard_iron_ut[i] + self.noise_ut * noise[i] for i in range(3))

    def load(self, t_us, reg):
        reg &= 0x7F
        if OUT_X_L <= reg < TEMP_OUT_L:
            per_ut = UT_PER_GAUSS / LSB_PER_GAUSS[self.regs[CTRL_REG2] >> 5 & 3]
            for i, value in enumerate(self.current(t_us)):
                put16(self.regs, OUT_X_L + 2 * i, counts(value, per_ut), False)
        return self.regs[reg]

    def write(self, t_us, byte):
        if not self.pointed:
            byte &= 0x7F  # (bit 7: the datasheet's auto-increment flag)
        return super().write(t_us, byte)

    def store(self, t_us, reg, value):
        if reg == WHO_AM_I or reg == STATUS_REG or OUT_X_L <= reg < OUT_END:
            return  # read-only
        self.regs[reg] = value & 0xFF

    def truth(self, t_us, plant) -> dict:
        horizontal, _vertical, north = self.field
        compass = math.degrees(north - self.heading_at(t_us) - self.mount_rad[2]) % 360.0
        return {f"{self.label}_heading_deg": compass}


class Lis3mdl(PartType):
    CHIP = Lis3mdlChip  # (its registers: docs/parts.md)
    kind = "lis3mdl"
    MODELLED_FEATURES = (
        "the field: the Earth's horizontal and vertical components as the body turns, a hard-iron offset, "
        "noise, saturation",
        "the output data rate and full scale as CTRL_REG1/2 set them; power-down stops the samples",
    )
    NOT_MODELLED = (
        "single-conversion mode (taken as continuous)",
        "self-test",
        "the interrupt pin and thresholds",
        "soft-iron distortion",
        "block data update (BDU)",
        "the temperature sensor (reads 0: 25 °C)",
    )
    doc = "An LIS3MDL-class 3-axis magnetometer (WHO_AM_I 0x3D) on I2C: the body's heading, a hard-iron offset."
    OPTIONS = (
        Opt("bus", BusName(), "i2c0", "the bus it is on, as the firmware creates it"),
        Opt("address", Num("", 0, 127, whole=True), 0x1C, "its 7-bit I2C address (0x1C; 0x1E with SDO high)"),
        Opt("horizontal_ut", Num("microtesla", 0, 100), 20.0, "the Earth's field's horizontal part"),
        Opt("vertical_ut", Num("microtesla", -100, 100), 44.0, "its downward part (negative: southern hemisphere)"),
        Opt("north_deg", Num("degrees", -360, 360), 90.0, "magnetic north, from the world's x axis (CCW)"),
        Opt(
            "hard_iron_ut",
            Row((Num("microtesla", -1000, 1000),) * 3, "[x, y, z] in microtesla"),
            [0.0, 0.0, 0.0],
            "the hard-iron offset: the robot's own field, turning with it, added to each axis",
        ),
        Opt("noise_ut", Num("microtesla", 0, 100), 0.3, "the noise on each axis (standard deviation, each sample)"),
    )
    TRUTH = ("{name}_heading_deg",)
    VIEWS = (View("heading", "the compass heading the field gives (clockwise from north)", truth=TRUTH),)
    on_bus = True
    needs_body = True

    @classmethod
    def options_at(cls, address: int, doc: str) -> tuple:
        """These options with another default address (a compass built on this one)."""
        at = Opt("address", Num("", 0, 127, whole=True), address, doc)
        return tuple(at if o.name == "address" else o for o in cls.OPTIONS)

    def check(self) -> None:
        check_placement(self.options, f"the {self.kind} part")

    def add(self, build: Build) -> None:
        o = self.options
        field = (float(o["horizontal_ut"]), float(o["vertical_ut"]), math.radians(o["north_deg"]))
        build.parts.append(
            self.CHIP(
                self.name,
                o["bus"],
                o["address"],
                mount_rad=self.mount_rad(),
                field=field,
                hard_iron_ut=o["hard_iron_ut"],
                noise_ut=o["noise_ut"],
                rng=build.rng,
            )
        )
