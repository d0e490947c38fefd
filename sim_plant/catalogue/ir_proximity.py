"""Part ``ir_proximity``: an infrared obstacle sensor with a comparator (an ST188 or
TCRT5000 reflective pair and an LM393, a potentiometer setting its distance: the Waveshare
Pico-Go's and AlphaBot2's two front sensors, the common "IR obstacle avoidance" modules): a
digital output, low while a wall is within ``threshold_m`` along its axis (``active_low``),
looked at every ``period_us``.

Not modelled: the reflectance of what is in front (a dark wall reflects less: on the
sensor the distance depends on it), the comparator's hysteresis, ambient light, the
module's LED."""

import math

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.engine import Part
from sim_plant.option_table import Flag, Num
from sim_plant.plant import Change
from sim_plant.sonars import BeamRangeModel


class _Proximity(Part):
    FIXED_STATE = ("inputs", "outputs", "signal", "label", "model")

    def __init__(self, name: str, model, threshold_m: float, period_us: int, active_low: bool):
        self.label = name
        self.signal = f"{name}.out"
        self.outputs = {self.signal: "level"}
        self.model = model
        self.threshold_m = threshold_m
        self.period_us = period_us
        self.near_level = 0 if active_low else 1
        self.level = 1 - self.near_level
        self.range_m = math.inf
        self.next_us = 0

    def initial_outputs(self) -> dict:
        return {self.signal: self.level}

    def fire(self, t_us: int, plant, out: list) -> None:
        self.range_m, reading = self.model.measure(t_us, plant.pose_at(t_us), plant.world, plant.rng)
        near = reading is not None and reading <= self.threshold_m
        level = self.near_level if near else 1 - self.near_level
        if level != self.level:
            self.level = level
            out.append(Change(t_us, self.signal, level))
        self.next_us = t_us + self.period_us

    def truth(self, t_us: int, plant) -> dict:
        return {f"{self.label}_range_m": self.range_m, f"{self.label}_near": self.level == self.near_level}


class IrProximity(PartType):
    kind = "ir_proximity"
    doc = (
        "An infrared obstacle sensor with a comparator (ST188 or TCRT5000 and an LM393): a digital level, low"
        " while a wall is within threshold_m along its axis."
    )
    OPTIONS = (
        Opt("threshold_m", Num("metres", 0.005, 1), 0.1, "the distance the module's potentiometer sets"),
        Opt("noise_sd_m", Num("metres", 0, 1), 0.0, "Gaussian noise on the distance compared"),
        Opt("period_us", Num("microseconds", 100, 1_000_000, whole=True), 1_000, "the wall is looked at every"),
        Opt("active_low", Flag(), True, "true: reads 0 while something is near (the LM393's open collector)"),
    )
    SIGNALS = (Sig("out", "out", "level", "the comparator's output"),)
    TRUTH = ("{name}_range_m", "{name}_near")
    VIEWS = (View("level", "the output against whether a wall is near", signals=("out",), truth=("{name}_near",)),)
    needs_body = True

    def add(self, build: Build) -> None:
        o = self.options
        model = BeamRangeModel(self.mount_rad(), noise_sd_m=o["noise_sd_m"], min_m=0.0, max_m=1.0, no_echo="none")
        build.parts.append(_Proximity(self.name, model, o["threshold_m"], o["period_us"], o["active_low"]))
