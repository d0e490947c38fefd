"""Part ``hcsr04``: an HC-SR04 ultrasonic ranger mounted anywhere on the body (a front
and a rear one are two tables), as its TRIG and ECHO pins, fixed or on a ``servo``
part's horn (``on_servo``: it then looks along the horn) (:mod:`sim_plant.physics.hcsr04`)."""

import numpy as np

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.controls import Control
from sim_plant.option_table import Name, Num
from sim_plant.physics import hcsr04


class _Named(hcsr04.HcSr04):
    """The module, its truth keys after its part's name (two rangers, two sets)."""

    def __init__(self, label: str, controls=None, **options):
        super().__init__(**options)
        self.label = label
        self.controls = controls
        self.inputs = {self.trig: "level"}  # a servo it rides on is its own part, with its own input

    def _ping(self, t_us: int, plant) -> None:
        """A ping; with its ``distance`` control set, the echo says that distance, exactly."""
        distance_cm = self.controls.value_at(self.label, "distance", t_us) if self.controls else None
        if distance_cm is None:
            return super()._ping(t_us, plant)
        self.pings += 1
        angle_deg = self.servo.angle_at(t_us) if self.servo is not None else 90.0
        self.last = {"ping_t_us": t_us, "ping_range_m": distance_cm / 100.0, "ping_angle_deg": angle_deg}
        self.rise_us = t_us + hcsr04.START_DELAY_US
        self.fall_us = self.rise_us + hcsr04.echo_width_us(distance_cm / 100.0)
        self.next_us = self.rise_us

    def truth(self, t_us: int, plant) -> dict:
        truth = super().truth(t_us, plant)
        return {f"{self.label}_{k}": v for k, v in truth.items() if not k.startswith("servo_")}


class HcSr04(PartType):
    kind = "hcsr04"
    doc = "HC-SR04 ultrasonic ranger: TRIG in, ECHO high for the round trip (58.31 us per cm), 4 cm to 4 m."
    OPTIONS = (
        Opt("noise_sd_m", Num("metres", 0, 10), 0.003, "Gaussian range noise"),
        Opt(
            "trigger_min_us",
            Num("microseconds", 1, 1_000, whole=True),
            2,
            "shortest TRIG pulse the module answers (datasheet: 10)",
        ),
        Opt("cone_deg", Num("degrees", 0, 180, above=True), hcsr04.CONE_DEG, "the beam's full angle"),
        Opt("max_range_m", Num("metres", 0.05, 10), hcsr04.MAX_RANGE_M, "farther obstacles time out (38 ms)"),
        Opt(
            "on_servo",
            Name(),
            None,
            "the name of a servo part (listed before this one) it rides on; unset: fixed on the body",
        ),
    )
    SIGNALS = (
        Sig("trig", "in", "level", "TRIG: a pulse starts a ping when it falls"),
        Sig("echo", "out", "level", "ECHO: high for the sound's round trip"),
    )
    TRUTH = ("{name}_ping_t_us", "{name}_ping_range_m", "{name}_ping_angle_deg")
    VIEWS = (
        View(
            "range",
            "the range the firmware read (echo width) against the true range",
            signals=("echo",),
            truth=("{name}_ping_range_m",),
        ),
    )
    needs_body = True
    CONTROLS = (
        Control(
            "distance", Num("centimetres", 2, 400), "the obstacle's distance; each ping from then on says it exactly"
        ),
    )

    def reading(self, suffix: str, values):
        """The range (m) an ECHO high time (us) says, as firmware computes it; NaN for a
        time-out (38 ms: nothing within range)."""
        return np.where(values >= hcsr04.TIMEOUT_US, np.nan, values / hcsr04.US_PER_CM / 100.0)

    def add(self, build: Build) -> None:
        o = self.options
        servo = None
        if o["on_servo"] is not None:
            servo = build.servos.get(o["on_servo"])
            if servo is None:
                raise ValueError(f"on_servo: no servo part named {o['on_servo']!r} before this part")
        build.parts.append(
            _Named(
                self.name,
                controls=build.controls,
                trig=f"{self.name}.trig",
                echo=f"{self.name}.echo",
                mount=self.mount_rad(),
                noise_sd_m=o["noise_sd_m"],
                max_range_m=o["max_range_m"],
                cone_deg=o["cone_deg"],
                trigger_min_us=o["trigger_min_us"],
                servo=servo,
            )
        )
