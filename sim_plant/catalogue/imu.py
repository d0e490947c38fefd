"""A 6-axis IMU's physics and its sampling, shared by the chip models
(``sim_plant/catalogue/mpu6050.py``, ``lsm6dsox.py``): what a chip's output registers say
at an output-data-rate tick, from the plant's truth.

- **gyro** (sensor axes, deg/s): the body's turn rate about z, plus a constant bias and
  Gaussian noise per sample, saturated at the configured full scale;
- **accelerometer** (m/s²): along the mount's heading the body's forward acceleration
  (its speed's change over :data:`ACCEL_WINDOW_US`), across it the centripetal v·w, and
  +g on z (the chip flat, face up); plus noise;
- the sample is taken at the last tick of the output data rate at or before the read (a
  read between two ticks gets the same sample, and the chip's ``DATA_READY`` bits say
  whether it is new, :class:`sim_plant.buses.DataReady`);
  a data-ready pin (``<name>.int``) rises at each tick while enabled and falls when the
  data are read.

The body's speeds are piecewise constant between motion changes; the part keeps their
recent history (``on_motion_change``) so that a tick is evaluated at its own time.
"""

import math

from sim_plant.buses import (
    NEVER_US,
    BusName,
    Change,
    RegisterDevice,
    check_placement,
    chip_select,
    tick_after,
)
from sim_plant.catalogue.base import CS_OPTION, CS_SIGNAL, SCK_SIGNAL, Build, Opt, PartType, Sig, View
from sim_plant.option_table import Flag, Num, Row

G_M_S2 = 9.80665
ACCEL_WINDOW_US = 10_000
HISTORY = 16  # motion changes kept (those before the oldest tick still wanted are dropped)


class Imu(RegisterDevice):
    """A register-level IMU. A chip model sets its registers' meaning through
    :meth:`gyro_scale`, :meth:`accel_scale`, :meth:`period_us`, :meth:`drdy_enabled` and
    its ``RESET`` map; this class keeps the samples and the data-ready line."""

    READS_STEADY = True  # its reads change only at its output data rate's ticks and its own events (busimage)

    def __init__(self, name, bus, address, mount_rad, *, gyro_bias_dps, gyro_noise_dps, accel_noise_m_s2, rng):
        super().__init__(name, bus, address)
        self.heading_rad = mount_rad[2]
        self.gyro_bias_dps = tuple(float(b) for b in gyro_bias_dps)
        self.gyro_noise_dps = float(gyro_noise_dps)
        self.accel_noise_m_s2 = float(accel_noise_m_s2)
        self.int_signal = f"{name}.int"
        self.outputs = {self.int_signal: "level"}
        self.history = [(0, 0.0, 0.0)]  # (t_us, v_m_s, w_rad_s) from then on
        self.sample_no = -1  # the tick of the sample held
        self.sample = (0, 0, 0, 0, 0, 0)  # gyro x, y, z (deg/s), accel x, y, z (m/s²)
        self.int_level = 0
        self.int_fall = False
        self.rng = rng  # (the plant's generator: shared, its state saved by snapshots)

    # -- a chip's registers say these -------------------------------------------------------

    def period_us(self) -> int:
        """The output data rate's period (0: powered down, the data hold)."""
        return 0

    def drdy_enabled(self) -> bool:
        return False

    # -- engine part ------------------------------------------------------------------------

    def initial_outputs(self) -> dict:
        return {self.int_signal: 0}

    def on_motion_change(self, t_us, plant) -> None:
        body = plant.drive.body
        self.history.append((t_us, float(body.v), float(body.w)))
        if len(self.history) > HISTORY:
            del self.history[0]

    def fire(self, t_us, plant, out) -> None:
        if self.int_fall:
            self.int_fall = False
            if self.int_level:
                self.int_level = 0
                out.append(Change(t_us, self.int_signal, 0))
        elif not self.int_level and self.drdy_enabled():
            self.int_level = 1
            out.append(Change(t_us, self.int_signal, 1))
        self.rearm(t_us)

    def _written(self, t_us: int, reg: int, value: int) -> None:
        super()._written(t_us, reg, value)
        if self.SELF_CLEARING:
            self.rearm(t_us)  # (a software reset: the rate and the line as the reset left them)

    def rearm(self, t_us: int) -> None:
        """Plan the data-ready line's next edge (after a configuration write, a read)."""
        period = self.period_us()
        if self.int_fall:
            self.next_us = t_us
        elif period and self.drdy_enabled():
            self.next_us = tick_after(t_us, period)
        else:
            self.next_us = NEVER_US

    def truth(self, t_us, plant) -> dict:
        _v, w = self._speeds(t_us)
        return {f"{self.label}_rate_dps": math.degrees(w), f"{self.label}_sample_dps": self.sample[2]}

    # -- samples ----------------------------------------------------------------------------

    def _speeds(self, t_us: int) -> tuple[float, float]:
        for t0, v, w in reversed(self.history):
            if t0 <= t_us:
                return v, w
        return self.history[0][1], self.history[0][2]

    def current(self, t_us: int) -> tuple:
        """The sample the output registers hold at ``t_us``."""
        period = self.period_us()
        if period:
            tick = t_us // period
            if tick != self.sample_no:
                self.sample_no = tick
                self.sample = self._measure(tick * period)
        return self.sample

    def taken(self, t_us: int) -> None:
        """The data registers were read: the data-ready line falls at once (the status
        bits: the chip's ``DATA_READY``)."""
        if self.int_level:
            self.int_fall = True
            self.next_us = t_us

    def _measure(self, t_us: int) -> tuple:
        v, w = self._speeds(t_us)
        v_before, _ = self._speeds(t_us - ACCEL_WINDOW_US)
        forward = (v - v_before) / (ACCEL_WINDOW_US * 1e-6)
        lateral = v * w
        c, s = math.cos(self.heading_rad), math.sin(self.heading_rad)
        n0, n1, n2, n3, n4, n5 = self.rng.standard_normal(6).tolist()  # (Python floats: cheaper arithmetic)
        bx, by, bz = self.gyro_bias_dps
        gn, an = self.gyro_noise_dps, self.accel_noise_m_s2
        return (  # gyro x, y, z: the turn rate about z; accel x, y, z: forward and lateral as mounted, and g
            0.0 + bx + gn * n0,
            0.0 + by + gn * n1,
            math.degrees(w) + bz + gn * n2,
            (c * forward + s * lateral) + an * n3,
            (-s * forward + c * lateral) + an * n4,
            G_M_S2 + an * n5,
        )


def counts(value: float, per_count: float) -> int:
    """A reading in a 16-bit two's-complement register, ``per_count`` a count (the
    datasheet's sensitivity), saturated at the register's ends (the full scale)."""
    return max(-32768, min(32767, round(value / per_count)))


def put16(regs: list, reg: int, value: int, big_endian: bool) -> None:
    """``value`` (a signed 16-bit count) into two registers from ``reg``."""
    high, low = (value >> 8) & 0xFF, value & 0xFF
    regs[reg], regs[reg + 1] = (high, low) if big_endian else (low, high)


class ImuPart(PartType):
    """What the IMU parts share: the bus, the address (I2C) or the chip select (SPI), the
    errors, the signals and views; a chip's part names its engine class (``CHIP``)."""

    CHIP = Imu
    SIGNALS = (
        Sig("int", "out", "level", "the data-ready interrupt line (rises at each new sample while enabled)"),
        CS_SIGNAL,
    )
    TRUTH = ("{name}_rate_dps", "{name}_sample_dps")
    VIEWS = (
        View(
            "rate",
            "the gyro's z reading against the body's true turn rate",
            truth=("{name}_rate_dps", "{name}_sample_dps"),
        ),
    )
    on_bus = True

    @staticmethod
    def bus_options(default_address: int) -> tuple:
        """The options every IMU part has (its chip's default address)."""
        return (
            Opt("bus", BusName(), "i2c0", "the bus it is on, as the firmware creates it"),
            Opt("address", Num("", 0, 127, whole=True), default_address, "its 7-bit I2C address"),
            Opt("spi", Flag(), False, "true: on an SPI bus, selected by its cs input (no address)"),
            CS_OPTION,
            Opt("holds_bus", Flag(), False, "true: it holds SDA low (a stuck bus: every transfer times out)"),
            Opt(
                "gyro_bias_dps",
                Row((Num("deg/s", -100, 100),) * 3, "[x, y, z] in deg/s"),
                [0.0, 0.0, 0.0],
                "the gyro's bias",
            ),
            Opt("gyro_noise_dps", Num("deg/s", 0, 100), 0.05, "the gyro's noise (standard deviation, each sample)"),
            Opt("accel_noise_m_s2", Num("m/s²", 0, 100), 0.02, "the accelerometer's noise (standard deviation)"),
        )

    def check(self) -> None:
        check_placement(self.options)

    def signals(self) -> dict[str, tuple[str, str]]:
        signals = {f"{self.name}.int": ("out", "level")}
        if CS_SIGNAL.present(self.options):
            signals[f"{self.name}.cs"] = ("in", "level")
        if SCK_SIGNAL.present(self.options):
            signals[f"{self.name}.sck"] = ("in", "level")
        return signals

    def engine(self, build: Build):
        o = self.options
        device = self.CHIP(
            self.name,
            o["bus"],
            None if o["spi"] else o["address"],
            self.mount_rad(),
            gyro_bias_dps=o["gyro_bias_dps"],
            gyro_noise_dps=o["gyro_noise_dps"],
            accel_noise_m_s2=o["accel_noise_m_s2"],
            rng=build.rng,
        )
        device.holds_bus = o["holds_bus"]
        return chip_select(device, o)

    def add(self, build: Build) -> None:
        build.parts.append(self.engine(build))
