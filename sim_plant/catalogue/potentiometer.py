"""Part ``potentiometer``: a knob between ground and the supply, its wiper on an ADC pin:
``read_u16`` gives the wiper's share of the supply against the ADC's full scale (a
Wokwi ``wokwi-potentiometer``'s ``value`` 0..1023 is ``position`` = value / 1023)."""

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.controls import Control
from sim_plant.engine import Part
from sim_plant.option_table import Num

FULL_U16 = 65535


def adc_u16(volts: float, vref_v: float) -> int:
    """What ``read_u16`` gives for ``volts`` on an ADC of full scale ``vref_v`` (clipped)."""
    return max(0, min(FULL_U16, round(volts / vref_v * FULL_U16)))


class Constant(Part):
    """Outputs that hold their values (a knob nobody turns, a switch nobody slides)."""

    FIXED_STATE = True

    def __init__(self, values: dict, kinds: dict):
        self.values = dict(values)
        self.outputs = dict(kinds)

    def initial_outputs(self) -> dict:
        return dict(self.values)


class Potentiometer(PartType):
    kind = "potentiometer"
    doc = "A knob (potentiometer) from ground to the supply, its wiper on an ADC pin: a fixed reading."
    OPTIONS = (
        Opt("position", Num("", 0, 1), 0.5, "the wiper's place, 0 (at ground) to 1 (at the supply)"),
        Opt("supply_v", Num("volts", 0, 50), 3.3, "the voltage across the track (3V3 or 5V)"),
        Opt("adc_vref_v", Num("volts", 0.1, 50), 3.3, "the ADC's full scale"),
    )
    SIGNALS = (Sig("sig", "out", "u16", "the wiper's voltage as read_u16 reads it"),)
    TRUTH = ()
    VIEWS = (View("level", "the wiper's reading", signals=("sig",)),)

    CONTROLS = (Control("position", Num("", 0, 1), "the wiper's place from then on, 0 to 1 (Wokwi's control)"),)

    def volts(self, position=None) -> float:
        return (self.options["position"] if position is None else position) * self.options["supply_v"]

    def control_change(self, control: str, value) -> tuple | None:
        super().control_change(control, value)
        return f"{self.name}.sig", adc_u16(self.volts(value), self.options["adc_vref_v"])

    def add(self, build: Build) -> None:
        reading = adc_u16(self.volts(), self.options["adc_vref_v"])
        build.parts.append(Constant({f"{self.name}.sig": reading}, {f"{self.name}.sig": "u16"}))
