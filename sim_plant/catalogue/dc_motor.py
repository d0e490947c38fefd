"""Part ``dc_motor``: a DC gear motor behind one H-bridge channel, driving a wheel of
the body (:mod:`sim_plant.motors`: the bridges' truth tables and :class:`DcMotor`)."""

import math

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.motors import DcMotor, DirPinsPwmBridge, DirPwmBridge, GangedBridges, TwoPwmBridge
from sim_plant.option_table import Num, OneOf

BRIDGES = {"tb6612": DirPinsPwmBridge, "l298n": DirPinsPwmBridge, "drv8833": TwoPwmBridge, "dir_pwm": DirPwmBridge}
PINS_PWM = ("tb6612", "l298n")


def _reversed(bridge_cls):
    """The bridge with its motor leads swapped: the same pins turn the wheel backwards."""

    class Reversed(bridge_cls):
        def effective(self):
            duty, braking = super().effective()
            return -duty, braking

    return Reversed


class DcMotorPart(PartType):
    kind = "dc_motor"
    doc = "A DC gear motor on one H-bridge channel (TB6612, L298N, DRV8833 or DIR+PWM), driving a wheel."
    OPTIONS = (
        Opt("bridge", OneOf(tuple(BRIDGES)), "tb6612", "the H-bridge and so its pins"),
        Opt(
            "drives",
            OneOf(("left", "right", "rear")),
            "left",
            "the wheel it turns (rear: a car's rear axle); two motors on one side (a four-wheel car's front "
            "and rear): that side at the mean of their duties, the first one's speed and lag",
        ),
        Opt("polarity", OneOf((-1, 1)), 1, "-1: leads swapped, the wheel turns backwards for a forward command"),
        Opt(
            "time_constant_ms",
            Num("milliseconds", 0, 10_000),
            40.0,
            "first-order speed lag (an N20 gear motor: 20-100 ms)",
        ),
        Opt("gain", Num("gain", 0, 10), 1.0, "speed at full duty relative to its nominal (a mismatched pair)"),
        Opt("deadband_duty", Num("duty", 0, 0.99), 0.1, "duty at or below which the wheel does not turn"),
        Opt(
            "rpm",
            Num("revolutions per minute", 0, 100_000, above=True, none=True),
            None,
            "no-load motor speed before the gearbox; unset: the body's v_max_m_s",
        ),
        Opt("gear_ratio", Num("motor turns per wheel turn", 0.01, 10_000), 20.0, "the gearbox (with rpm)"),
    )
    SIGNALS = (
        Sig("in1", "in", "level", "direction pin 1", (("bridge", PINS_PWM),)),
        Sig("in2", "in", "level", "direction pin 2", (("bridge", PINS_PWM),)),
        Sig("pwm", "in", "duty", "speed (PWM enable)", (("bridge", (*PINS_PWM, "dir_pwm")),)),
        Sig("in1", "in", "duty", "PWM forward", (("bridge", ("drv8833",)),)),
        Sig("in2", "in", "duty", "PWM backward", (("bridge", ("drv8833",)),)),
        Sig("dir", "in", "level", "direction", (("bridge", ("dir_pwm",)),)),
    )
    TRUTH = ()
    VIEWS = (View("command", "the signed command the bridge's pins make", signals=("in1", "in2", "pwm", "dir")),)
    needs_body = True

    def add(self, build: Build) -> None:
        o = self.options
        wheel_radius_m = build.body["wheel_radius_m"]
        if o["rpm"] is None:
            max_rad_s = build.body["v_max_m_s"] / wheel_radius_m
        else:
            max_rad_s = o["rpm"] / o["gear_ratio"] * 2 * math.pi / 60
        bridge_cls = BRIDGES[o["bridge"]]
        bridge = (_reversed(bridge_cls) if o["polarity"] < 0 else bridge_cls)(self.name)
        motor = DcMotor(
            max_wheel_rad_s=max_rad_s,
            deadband_duty=o["deadband_duty"],
            gain=o["gain"],
            time_constant_ms=o["time_constant_ms"],
        )
        if o["drives"] in build.motors:  # (a four-wheel car: a second motor on that side, geared to it by the ground)
            ganged, first = build.motors[o["drives"]]
            members = ganged.members if isinstance(ganged, GangedBridges) else [ganged]
            build.motors[o["drives"]] = (GangedBridges([*members, bridge]), first)
            return
        build.motors[o["drives"]] = (bridge, motor)
