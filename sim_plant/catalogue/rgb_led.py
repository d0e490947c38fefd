"""Part ``rgb_led``: a three-colour LED on three board outputs (``<name>.r``, ``.g``,
``.b``: levels, or PWM duties with ``signal = "duty"``), common cathode (an output lights
its colour high) or common anode (low). The truth holds each colour's brightness, 0 to 1,
and the colour it shows as ``0xRRGGBB``."""

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.engine import Part
from sim_plant.option_table import OneOf

COLOURS = ("r", "g", "b")
FULL_U16 = 65535


class _RgbLed(Part):
    FIXED_STATE = ("inputs", "outputs")

    def __init__(self, name: str, duty: bool, anode: bool):
        self.label, self.duty, self.anode = name, duty, anode
        self.inputs = {f"{name}.{c}": "duty" if duty else "level" for c in COLOURS}
        self.values = dict.fromkeys(COLOURS, 0)

    def set_input(self, name: str, value, t_us: int, plant) -> bool:
        self.values[name.rsplit(".", 1)[1]] = int(value)
        return False

    def brightness(self, colour: str) -> float:
        share = self.values[colour] / FULL_U16 if self.duty else float(bool(self.values[colour]))
        return 1.0 - share if self.anode else share

    def truth(self, t_us: int, plant) -> dict:
        shares = [self.brightness(c) for c in COLOURS]
        rgb = 0
        for share in shares:
            rgb = rgb << 8 | round(share * 255)
        truth = {f"{self.label}_{c}": s for c, s in zip(COLOURS, shares)}
        truth[f"{self.label}_rgb"] = rgb
        return truth


class RgbLed(PartType):
    kind = "rgb_led"
    doc = "A three-colour LED on three outputs (levels or PWM), common cathode or anode: its colour in the truth."
    OPTIONS = (
        Opt("common", OneOf(("cathode", "anode")), "cathode", "cathode: a high output lights; anode: a low one"),
        Opt("signal", OneOf(("level", "duty")), "level", "the pins' levels or PWM duties (duty_u16)"),
    )
    SIGNALS = tuple(Sig(c, "in", "level or duty", f"the {c.upper()} pin") for c in COLOURS)
    TRUTH = ("{name}_r", "{name}_g", "{name}_b", "{name}_rgb")
    VIEWS = (View("level", "each colour's pin over time", signals=COLOURS, truth=("{name}_rgb",)),)

    def signals(self) -> dict[str, tuple[str, str]]:
        return {f"{self.name}.{c}": ("in", self.options["signal"]) for c in COLOURS}

    def add(self, build: Build) -> None:
        o = self.options
        build.parts.append(_RgbLed(self.name, o["signal"] == "duty", o["common"] == "anode"))
