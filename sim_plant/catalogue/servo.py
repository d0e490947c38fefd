"""Part ``servo``: a hobby servo on a 50 Hz PWM (SG90 style), positional (the pulse sets
the angle, reached at a fixed slew rate) or continuous (the pulse sets the speed, 1.5 ms
still). A part mounted on it (an ``hcsr04`` with ``on_servo``) looks along the servo's
horn: 90 degrees (positional) or its start angle is the mount's own heading
(:class:`sim_plant.hcsr04.Servo`)."""

import math

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.engine import Part
from sim_plant.hcsr04 import Servo as PositionalServo
from sim_plant.option_table import Num, OneOf


class ContinuousServo(PositionalServo):
    """A continuous-rotation servo: the pulse's distance from the middle of the span sets
    the speed (full speed at either end), a small band around the middle stands still."""

    STILL_FRACTION = 0.02  # of the half span, around 1.5 ms

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
            pulse_us = int(duty_u16) / 65535 * self.period_us
            half_span = (self.max_pulse_us - self.min_pulse_us) / 2
            k = max(-1.0, min(1.0, (pulse_us - self.min_pulse_us - half_span) / half_span))
            rate = 0.0 if abs(k) <= self.STILL_FRACTION else k * self.deg_per_us
        self.rate_deg_per_us = rate
        self.target_deg = math.inf if rate > 0 else (-math.inf if rate < 0 else self.angle0_deg)


class _ServoPart(Part):
    """The servo's PWM input; its angle in the truth."""

    def __init__(self, name: str, servo):
        self.label = name
        self.servo = servo
        self.inputs = {servo.name: "duty"}

    def set_input(self, name: str, value, t_us: int, plant) -> bool:
        self.servo.set_duty(t_us, value)
        return False

    def truth(self, t_us: int, plant) -> dict:
        return {f"{self.label}_deg": self.servo.angle_at(t_us), f"{self.label}_target_deg": self.servo.target_deg}


class Servo(PartType):
    kind = "servo"
    doc = "A hobby servo on a 50 Hz PWM: positional (pulse -> angle) or continuous (pulse -> speed); parts ride on it."
    OPTIONS = (
        Opt("mode", OneOf(("positional", "continuous")), "positional", "the pulse sets the angle, or the speed"),
        Opt("pwm_freq_hz", Num("hertz", 1, 1_000), 50.0, "the PWM frequency the board drives it at"),
        Opt("min_pulse_us", Num("microseconds", 100, 5_000), 500.0, "the pulse for 0 degrees (full speed back)"),
        Opt("max_pulse_us", Num("microseconds", 100, 5_000), 2500.0, "the pulse for range_deg (full speed on)"),
        Opt("range_deg", Num("degrees", 1, 360), 180.0, "the positional servo's travel"),
        Opt(
            "deg_per_s", Num("degrees per second", 0, 100_000, above=True), 500.0, "slew rate (SG90: 60 deg in 0.12 s)"
        ),
        Opt("start_deg", Num("degrees", -360, 360), 90.0, "its angle at reset (90: along the mount's heading)"),
    )
    SIGNALS = (Sig("pwm", "in", "duty", "the control pulse (duty_u16 at pwm_freq_hz)"),)
    TRUTH = ("{name}_deg", "{name}_target_deg")
    VIEWS = (View("angle", "the horn's angle against its commanded target", signals=("pwm",), truth=("{name}_deg",)),)

    def check(self) -> None:
        o = self.options
        if o["min_pulse_us"] >= o["max_pulse_us"]:
            raise ValueError(
                f"min_pulse_us: expected less than max_pulse_us ({o['max_pulse_us']}), got {o['min_pulse_us']}"
            )

    def add(self, build: Build) -> None:
        o = self.options
        make = ContinuousServo if o["mode"] == "continuous" else PositionalServo
        servo = make(
            f"{self.name}.pwm",
            pwm_freq_hz=o["pwm_freq_hz"],
            min_pulse_us=o["min_pulse_us"],
            max_pulse_us=o["max_pulse_us"],
            range_deg=o["range_deg"],
            deg_per_s=o["deg_per_s"],
            start_deg=o["start_deg"],
        )
        build.servos[self.name] = servo
        build.parts.append(_ServoPart(self.name, servo))
