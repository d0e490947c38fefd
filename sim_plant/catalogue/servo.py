"""Part ``servo``: a hobby servo (SG90, MG996R) on a PWM pin. The pulse width sets the
horn's angle (positional: ``min_pulse_us`` at 0 degrees, ``max_pulse_us`` at
``range_deg``, reached at ``slew_deg_per_s``) or the shaft's speed (continuous: the middle
pulse stops it, the ends turn it at ``rpm`` either way). The firmware's ``duty_u16`` (or
``duty_ns``) at ``freq_hz`` gives the pulse; no pulses leave it where it is.

A part mounted on it (an ``hcsr04`` with ``on_servo``) looks along the servo's horn: 90
degrees is the mount's own heading (:class:`sim_plant.physics.hcsr04.Servo`, whose motion this
part wraps). A servo with ``steers = true`` turns the front wheels of an ``ackermann``
body (the body's drive takes it and follows its travel in steps); any other servo just
turns (a sonar's pan, a gripper)."""

import math

import numpy as np

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.engine import Part
from sim_plant.option_table import Flag, Num, OneOf
from sim_plant.physics.hcsr04 import Servo as PositionalMotion
from sim_plant.plant import NEVER_US

DUTY_FULL = 65535
STEP_US = 5_000  # a drive that owns the servo (the ackermann's) follows its travel in steps of this


class ContinuousMotion(PositionalMotion):
    """A continuous-rotation servo: the pulse's distance from the middle of the span sets
    the speed (full speed at either end), a small band around the middle stands still."""

    STILL_FRACTION = 0.02  # of the half span, around the middle pulse

    def __init__(self, name: str, **options):
        super().__init__(name, **options)
        self.rate_deg_per_us = 0.0

    def angle_at(self, t_us: int) -> float:
        return self.angle0_deg + self.rate_deg_per_us * (t_us - self.t0_us)

    def settle_us(self) -> int:
        return self.t0_us

    def set_duty(self, t_us: int, duty_u16: int) -> None:
        self.angle0_deg = self.angle_at(t_us)
        self.t0_us = t_us
        rate = 0.0
        if int(duty_u16) > 0:
            pulse_us = int(duty_u16) / DUTY_FULL * self.period_us
            half_span = (self.max_pulse_us - self.min_pulse_us) / 2
            k = max(-1.0, min(1.0, (pulse_us - self.min_pulse_us - half_span) / half_span))
            rate = 0.0 if abs(k) <= self.STILL_FRACTION else k * self.deg_per_us
        self.rate_deg_per_us = rate
        self.target_deg = math.inf if rate > 0 else (-math.inf if rate < 0 else self.angle0_deg)


class ServoModel(Part):
    """One servo: its PWM input, the motion it makes of the pulse, its angle in the truth.
    On its own it schedules nothing (its angle is a function of time); a drive that owns it
    calls :meth:`step` while ``next_us`` says it still travels, and reads ``angle_deg``."""

    FIXED_STATE = ("inputs", "outputs")

    def __init__(self, name: str, o: dict):
        self.signal, self.label = f"{name}.pwm", name
        self.inputs = {self.signal: "duty"}
        self.continuous = o["type"] == "continuous"
        self.steers = bool(o["steers"])
        start_deg = o["start_deg"]
        if start_deg is None:
            start_deg = 0.0 if self.continuous else float(o["range_deg"]) / 2  # (positional: centred)
        self.motion = (ContinuousMotion if self.continuous else PositionalMotion)(
            self.signal,
            pwm_freq_hz=float(o["freq_hz"]),
            min_pulse_us=float(o["min_pulse_us"]),
            max_pulse_us=float(o["max_pulse_us"]),
            range_deg=float(o["range_deg"]),
            deg_per_s=float(o["rpm"]) * 6.0 if self.continuous else float(o["slew_deg_per_s"]),
            start_deg=float(start_deg),
        )
        self.pulse_us = 0.0
        self.angle_deg = self.motion.angle_at(0)  # as the owning drive last stepped it
        self.owned = False  # True once a drive takes it (it then schedules its steps)
        self.next_us = NEVER_US

    def set_input(self, name: str, value, t_us: int, plant) -> bool:
        value = min(max(int(value), 0), DUTY_FULL)
        self.pulse_us = value / DUTY_FULL * self.motion.period_us
        self.motion.set_duty(t_us, value)
        if self.owned and self.next_us == NEVER_US and self.motion.settle_us() > t_us:
            self.next_us = t_us + STEP_US
        return False

    def step(self, t_us: int) -> None:
        """The horn where its motion has it at ``t_us``; ``next_us`` the next step while it travels."""
        self.angle_deg = self.motion.angle_at(t_us)
        self.next_us = t_us + STEP_US if self.motion.settle_us() > t_us else NEVER_US

    def truth(self, t_us: int, plant) -> dict:
        return {
            f"{self.label}_angle_deg": self.motion.angle_at(t_us),
            f"{self.label}_target_deg": self.motion.target_deg,
            f"{self.label}_pulse_us": self.pulse_us,
        }


class Servo(PartType):
    kind = "servo"
    doc = "A hobby servo on a PWM pin: the pulse width sets its angle (positional) or its speed (continuous)."
    OPTIONS = (
        Opt("type", OneOf(("positional", "continuous")), "positional", "an angle for a pulse, or a speed"),
        Opt("freq_hz", Num("hertz", 1, 1_000), 50.0, "the PWM frequency the firmware sets (servos: 50 Hz)"),
        Opt(
            "min_pulse_us", Num("microseconds", 100, 5_000), 500.0, "the pulse for 0 degrees (continuous: full reverse)"
        ),
        Opt(
            "max_pulse_us", Num("microseconds", 100, 5_000), 2_500.0, "the pulse for range_deg (continuous: full ahead)"
        ),
        Opt("range_deg", Num("degrees", 1, 360), 180.0, "the horn's travel between the two pulses"),
        Opt("slew_deg_per_s", Num("degrees per second", 1, 100_000), 600.0, "the fastest the horn turns (SG90: 600)"),
        Opt("rpm", Num("revolutions per minute", 0, 1_000), 100.0, "a continuous servo's speed at full pulse"),
        Opt(
            "start_deg",
            Num("degrees", -360, 360, none=True),
            None,
            "its angle at reset; by default centred (range_deg / 2; continuous: 0). 90: along a mounted part's heading",
        ),
        Opt("steers", Flag(), False, "true: it turns an ackermann body's front wheels"),
    )
    SIGNALS = (Sig("pwm", "in", "duty", "the control pulse: duty_u16 (or duty_ns) at freq_hz"),)
    TRUTH = ("{name}_angle_deg", "{name}_target_deg", "{name}_pulse_us")
    VIEWS = (
        View(
            "angle",
            "the angle the firmware's pulse asks for against the horn's true angle",
            signals=("pwm",),
            truth=("{name}_angle_deg",),
        ),
    )

    def check(self) -> None:
        o = self.options
        if o["min_pulse_us"] >= o["max_pulse_us"]:
            raise ValueError(
                f"min_pulse_us: expected less than max_pulse_us ({o['max_pulse_us']}), got {o['min_pulse_us']}"
            )
        if o["max_pulse_us"] >= 1e6 / o["freq_hz"]:
            raise ValueError(f"max_pulse_us: expected less than the PWM period at freq_hz ({1e6 / o['freq_hz']:g} us)")
        if o["steers"] and o["type"] != "positional":
            raise ValueError("steers: a steering servo is a positional one (type = 'positional')")

    def reading(self, suffix: str, values):
        """The angle (degrees) the firmware's duty_u16 asks for (NaN: no pulses)."""
        o = self.options
        pulse_us = values / DUTY_FULL * 1e6 / o["freq_hz"]
        share = np.clip((pulse_us - o["min_pulse_us"]) / (o["max_pulse_us"] - o["min_pulse_us"]), 0, 1)
        return np.where(values > 0, share * o["range_deg"], np.nan)

    def add(self, build: Build) -> None:
        model = ServoModel(self.name, self.options)
        build.servos[self.name] = model.motion  # what a part mounted on it turns with
        build.parts.append(model)
