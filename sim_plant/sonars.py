"""Range sonars read through an ADC, and the pieces every sonar shares.

A sonar is two objects (Gymnasium style: the true state and what a sensor reports are
kept apart, and another sensor is another object, not an ``if``):

* a **transducer model** turns the true geometry into the range the sensor would report
  (or ``None``: no echo), with its noise, limits and failure modes;
* an **output** part turns that into the electrical signal a board sees, at the sensor's
  update times: ADC counts here (:class:`AnalogRangeSonar`), NMEA bytes on a UART in
  :mod:`sim_plant.physics.echo_sounder`.

:class:`BeamRangeModel` is the plain model (range along the axis, Gaussian noise,
clamped to the sensor's span). The analog law defaults to a MaxBotix LV-EZ: Vcc/512
volts per inch, i.e. 0.2537 V/m at 3.3 V.
"""

import math

from sim_plant.engine import Part
from sim_plant.plant import NEVER_US, Change

MAXBOTIX_V_PER_M = 3.3 / 512 / 0.0254
"""MaxBotix LV-style analog output: Vcc/512 per inch, at Vcc = 3.3 V."""


class Adc:
    """A board's ADC: volts -> ``bits``-bit counts over 0..``vref_v``, reported as
    ``ADC.read_u16`` does (the n-bit reading scaled to 16 bits by repeating its top bits)."""

    FIXED_STATE = True  # configuration only

    def __init__(self, bits: int = 12, vref_v: float = 3.3):
        if not 1 <= bits <= 16 or vref_v <= 0:
            raise ValueError(f"Adc: bits must be 1..16 and vref_v > 0, got {bits}, {vref_v}")
        self.bits = bits
        self.vref_v = float(vref_v)
        self.max_counts = (1 << bits) - 1

    def counts(self, volts: float) -> int:
        c = round(volts / self.vref_v * self.max_counts)
        return 0 if c < 0 else (self.max_counts if c > self.max_counts else c)

    def u16(self, volts: float) -> int:
        """The reading as ``read_u16`` returns it."""
        return self.to_u16(self.counts(volts))

    def to_u16(self, counts: int) -> int:
        shift = 16 - self.bits
        value = counts << shift
        while shift > 0:  # repeat the top bits into the low ones
            shift -= self.bits
            value |= (counts << shift) if shift >= 0 else (counts >> -shift)
        return value


def sensor_pose(pose: tuple[float, float, float], mount: tuple[float, float, float]) -> tuple[float, float, float]:
    """World position and axis of a sensor mounted at ``(x_m, y_m, angle_rad)`` in the
    body frame (x forward, y left)."""
    x, y, th = pose
    mx, my, ma = mount
    co, si = math.cos(th), math.sin(th)
    return x + co * mx - si * my, y + si * mx + co * my, th + ma


class BeamRangeModel:
    """A plain ultrasonic ranger.

    ==========================  ========  ==============================================
    attribute                   default   meaning
    ==========================  ========  ==============================================
    ``mount``                   origin    ``(x_m, y_m, angle_rad)`` in the body frame
    ``offset_m``                0         subtracted: from the mount to the face ranges
                                          are measured from
    ``noise_sd_m``              0.01      Gaussian range noise
    ``min_m``, ``max_m``        0.03, 4   span; readings are clamped to it
    ``beam_half_angle_deg``     0         0: range along the axis; > 0: to the nearest
                                          wall point inside the beam
    ``max_incidence_deg``       90        no echo from a wall hit further off its normal
    ``dropout_p``               0         chance that an echo is missed
    ``no_echo``                 "max"     what a missed echo reads: ``"max"`` (``max_m``,
                                          as an analog ranger with nothing in view) or
                                          ``"none"`` (no reading: the output's invalid code)
    ==========================  ========  ==============================================
    """

    FIXED_STATE = True  # configuration only (measure draws from the plant's generator)

    def __init__(
        self,
        mount=(0.0, 0.0, 0.0),
        *,
        noise_sd_m: float = 0.01,
        min_m: float = 0.03,
        max_m: float = 4.0,
        offset_m: float = 0.0,
        beam_half_angle_deg: float = 0.0,
        max_incidence_deg: float = 90.0,
        dropout_p: float = 0.0,
        no_echo: str = "max",
    ):
        if no_echo not in ("max", "none"):
            raise ValueError(f"no_echo: 'max' or 'none', got {no_echo!r}")
        self.mount = tuple(float(v) for v in mount)
        self.noise_sd_m = float(noise_sd_m)
        self.min_m = float(min_m)
        self.max_m = float(max_m)
        self.offset_m = float(offset_m)
        self.beam_half_angle_rad = math.radians(beam_half_angle_deg)
        self.max_incidence_rad = math.radians(max_incidence_deg)
        self.dropout_p = float(dropout_p)
        self.no_echo = no_echo

    def measure(self, t_us: int, pose, world, rng) -> tuple[float, float | None]:
        """(true range, reported range or None)."""
        sx, sy, axis = sensor_pose(pose, self.mount)
        local = world.near(sx, sy, self.max_m + self.offset_m)
        hit_m, incidence = local.ray(sx, sy, axis)
        if self.beam_half_angle_rad > 0.0:
            hit_m = local.cone_nearest(sx, sy, axis, self.beam_half_angle_rad)
        true_m = hit_m - self.offset_m
        noisy_m = true_m + rng.normal(0.0, self.noise_sd_m)
        missed = incidence > self.max_incidence_rad or (self.dropout_p > 0.0 and rng.random() < self.dropout_p)
        if missed or true_m > self.max_m:
            return true_m, (self.max_m if self.no_echo == "max" else None)
        return true_m, min(max(noisy_m, self.min_m), self.max_m)


class AnalogRangeSonar(Part):
    """An analog ultrasonic ranger on an ADC pin: a new range every ``period_us``
    (first at ``phase_us``), ``volts_per_m`` volts per metre, read by ``adc``. A missing
    reading (``None`` from the model) reads ``invalid_v`` volts. Each new sample is a
    :class:`Change`, even when its value repeats: it is an event the firmware consumes."""

    def __init__(
        self,
        name: str,
        model,
        *,
        period_us: int = 500_000,
        phase_us: int = 20_000,
        volts_per_m: float = MAXBOTIX_V_PER_M,
        adc: Adc | None = None,
        invalid_v: float = 0.0,
    ):
        if period_us <= 0 or phase_us <= 0:
            raise ValueError(f"{name}: period_us and phase_us must be > 0")
        self.name = name
        self.model = model
        self.period_us = int(period_us)
        self.volts_per_m = float(volts_per_m)
        self.adc = adc or Adc()
        self.invalid_v = float(invalid_v)
        self.outputs = {name: "u16"}
        self.next_us = int(phase_us)
        self.true_m = math.inf
        self.reading_m: float | None = None
        self.value = self.adc.u16(getattr(model, "max_m", 0.0) * self.volts_per_m)  # before the first sample

    def initial_outputs(self) -> dict:
        return {self.name: self.value}

    def fire(self, t_us: int, plant, out: list) -> None:
        self.sample(t_us, plant, out)
        self.next_us = t_us + self.period_us

    def sample(self, t_us: int, plant, out: list) -> None:
        """Take a new reading at ``t_us`` and append it as a :class:`Change`."""
        self.true_m, self.reading_m = self.model.measure(t_us, plant.pose_at(t_us), plant.world, plant.rng)
        volts = self.invalid_v if self.reading_m is None else self.reading_m * self.volts_per_m
        self.value = self.adc.u16(volts)
        out.append(Change(t_us, self.name, self.value))

    def truth(self, t_us: int, plant) -> dict:
        key = self.name.split(".")[0]
        return {f"{key}_range_m": self.true_m, f"{key}_reading_m": self.reading_m}


class TriggeredSonar(AnalogRangeSonar):
    """An analog sonar that ranges once per trigger (:class:`SonarRx`): one new reading
    the ranging time after the RX edge, then nothing until the next edge."""

    def __init__(self, name: str, model, **kwargs):
        super().__init__(name, model, **kwargs)
        self.period_us = None  # the board sets the pace
        self.next_us = NEVER_US

    def fire(self, t_us: int, plant, out: list) -> None:
        self.sample(t_us, plant, out)
        self.next_us = NEVER_US


class SonarRx(Part):
    """The sonars' shared RX line (a MaxBotix chain's trigger): each rising edge starts a
    ranging of every sonar, read ``ranging_us`` later."""

    FIXED_STATE = ("inputs", "outputs", "sonars")

    def __init__(self, name: str, sonars: list, ranging_us: int):
        if ranging_us <= 0:
            raise ValueError(f"sonar_ranging_us must be > 0, got {ranging_us}")
        self.inputs = {name: "level"}
        self.sonars = sonars
        self.ranging_us = int(ranging_us)
        self.level = 0

    def set_input(self, name: str, value, t_us: int, plant) -> bool:
        level = 1 if value else 0
        if level and not self.level:
            for sonar in self.sonars:
                sonar.next_us = t_us + self.ranging_us
        self.level = level
        return False
