"""Part ``photoresistor``: a light-dependent resistor module (an LDR in series with 10 kOhm
from the supply to ground, as Wokwi's ``wokwi-photoresistor-sensor``): its analog
output ``<name>.ao`` (the LDR's share of the supply, read_u16) and its digital output
``<name>.do`` (high when dark: the analog voltage above ``threshold_v``). The LDR's
resistance at ``lux`` is ``rl10_kohm * (10 / lux) ** gamma``. With ``ldr_at = "supply"``
the LDR is the divider's upper arm (the Keyestudio Beetlebot's modules: "when the light
intensity is stronger, the analog value ... will increase"): ``ao`` is the 10 kOhm's share,
rising with the light; ``do`` is still high when dark (the LDR's share above
``threshold_v``)."""

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.catalogue.potentiometer import Constant, adc_u16
from sim_plant.controls import Control
from sim_plant.option_table import Num, OneOf

SERIES_OHM = 10_000.0


def ao_volts(lux: float, rl10_kohm: float, gamma: float, supply_v: float) -> float:
    """The module's analog output for ``lux``: the divider of the LDR and 10 kOhm."""
    ldr_ohm = rl10_kohm * 1e3 * (10.0 / lux) ** gamma
    return supply_v * ldr_ohm / (ldr_ohm + SERIES_OHM)


class Photoresistor(PartType):
    kind = "photoresistor"
    doc = "A light sensor module (LDR and 10 kOhm): an analog voltage for the light, and a dark/light level."
    OPTIONS = (
        Opt("lux", Num("lux", 0.01, 200_000), 500.0, "the light falling on it"),
        Opt("rl10_kohm", Num("kilo-ohms", 0.1, 10_000), 50.0, "the LDR's resistance at 10 lux"),
        Opt("gamma", Num("", 0.1, 2), 0.7, "the slope of log(R) against log(lux)"),
        Opt("threshold_v", Num("volts", 0, 50), 2.5, "the digital output is high above this (dark)"),
        Opt("supply_v", Num("volts", 0, 50), 3.3, "the module's supply (3V3 or 5V)"),
        Opt("adc_vref_v", Num("volts", 0.1, 50), 3.3, "the ADC's full scale"),
        Opt(
            "ldr_at",
            OneOf(("ground", "supply")),
            "ground",
            "the LDR's end of the divider: ground, ao rises as the light falls (Wokwi's module); supply, "
            "ao rises with the light",
        ),
    )
    SIGNALS = (
        Sig("ao", "out", "u16", "the analog output as read_u16 reads it"),
        Sig("do", "out", "level", "1 when dark (the analog output above threshold_v), 0 in light"),
    )
    TRUTH = ()
    VIEWS = (View("level", "the analog reading", signals=("ao",)),)

    CONTROLS = (Control("lux", Num("lux", 0.01, 200_000), "the light falling on it from then on (Wokwi's control)"),)

    def outputs_at(self, lux: float) -> dict:
        """The analog and digital outputs under ``lux``."""
        o = self.options
        volts = ao_volts(lux, o["rl10_kohm"], o["gamma"], o["supply_v"])
        ao = o["supply_v"] - volts if o["ldr_at"] == "supply" else volts
        return {f"{self.name}.ao": adc_u16(ao, o["adc_vref_v"]), f"{self.name}.do": int(volts > o["threshold_v"])}

    def control_change(self, control: str, value):
        super().control_change(control, value)
        return list(self.outputs_at(value).items())

    def add(self, build: Build) -> None:
        values = self.outputs_at(self.options["lux"])
        build.parts.append(Constant(values, {f"{self.name}.ao": "u16", f"{self.name}.do": "level"}))
