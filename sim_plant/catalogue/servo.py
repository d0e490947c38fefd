"""Part ``servo``: a hobby servo (SG90, MG996R) on a PWM pin. The pulse width sets the
horn's angle (positional: ``min_pulse_us`` at 0 degrees, ``max_pulse_us`` at
``range_deg``) or the shaft's speed (continuous: the middle pulse stops it, the ends turn
it at ``rpm`` either way); the horn turns at most ``slew_deg_per_s`` (an SG90: 60 degrees
in 0.1 s). The firmware's ``duty_u16`` (or ``duty_ns``) at ``freq_hz`` gives the pulse.

A servo with ``steers = true`` turns the front wheels of an ``ackermann`` body (the body
takes it as its steering); any other servo just turns (a sonar's pan, a gripper)."""

import numpy as np

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.engine import Part
from sim_plant.option_table import Flag, Num, OneOf
from sim_plant.plant import NEVER_US

DUTY_FULL = 65535
STEP_US = 5_000  # the horn's travel is followed in steps of this length


class ServoModel(Part):
    """One servo: the pulse it is given, the angle (or speed) it makes of it, its travel."""

    FIXED_STATE = ("inputs", "outputs")

    def __init__(self, name: str, o: dict):
        self.signal, self.label = f"{name}.pwm", name
        self.inputs = {self.signal: "duty"}
        self.continuous = o["type"] == "continuous"
        self.period_us = 1e6 / float(o["freq_hz"])
        self.min_us, self.max_us = float(o["min_pulse_us"]), float(o["max_pulse_us"])
        self.range_deg, self.rpm = float(o["range_deg"]), float(o["rpm"])
        self.slew_deg_per_step = float(o["slew_deg_per_s"]) * STEP_US / 1e6
        self.pulse_us = 0.0
        self.angle_deg = 0.0 if self.continuous else self.range_deg / 2  # (a positional servo: centred)
        self.target_deg = self.angle_deg
        self.turned_deg = 0.0  # a continuous servo's shaft, in total
        self.speed_deg_s = 0.0
        self.t_us = 0
        self.next_us = NEVER_US

    def set_input(self, name: str, value, t_us: int, plant) -> bool:
        self._turn(t_us)
        self.pulse_us = min(max(int(value), 0), DUTY_FULL) / DUTY_FULL * self.period_us
        if self.pulse_us <= 0:  # no pulses: the servo goes limp and stays where it is
            self.speed_deg_s = 0.0
            self.target_deg = self.angle_deg
            return False
        share = (min(max(self.pulse_us, self.min_us), self.max_us) - self.min_us) / (self.max_us - self.min_us)
        if self.continuous:
            self.speed_deg_s = (2 * share - 1) * self.rpm * 6.0
        else:
            self.target_deg = share * self.range_deg
            if self.target_deg != self.angle_deg and self.next_us == NEVER_US:
                self.next_us = t_us + STEP_US
        return False

    def _turn(self, t_us: int) -> None:
        self.turned_deg += self.speed_deg_s * (t_us - self.t_us) * 1e-6
        self.t_us = t_us

    def step(self, t_us: int) -> None:
        """The horn's travel over one step towards its target."""
        gap = self.target_deg - self.angle_deg
        move = max(-self.slew_deg_per_step, min(self.slew_deg_per_step, gap))
        self.angle_deg += move
        self.next_us = NEVER_US if self.angle_deg == self.target_deg else t_us + STEP_US

    def fire(self, t_us: int, plant, out: list) -> None:
        self.step(t_us)

    def truth(self, t_us: int, plant) -> dict:
        if self.continuous:
            self._turn(t_us)
            return {f"{self.label}_turned_deg": self.turned_deg, f"{self.label}_pulse_us": self.pulse_us}
        return {f"{self.label}_angle_deg": self.angle_deg, f"{self.label}_pulse_us": self.pulse_us}


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
        Opt("steers", Flag(), False, "true: it turns an ackermann body's front wheels"),
    )
    SIGNALS = (Sig("pwm", "in", "duty", "the control pulse: duty_u16 (or duty_ns) at freq_hz"),)
    TRUTH = ("{name}_angle_deg", "{name}_pulse_us")
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
        model.steers = self.options["steers"]
        build.parts.append(model)
