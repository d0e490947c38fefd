"""Part ``ir_distance``: a Sharp GP2Y0A21YK infrared distance sensor (10 to 80 cm) on an
ADC pin. Its output voltage falls as the inverse of the range (datasheet figure: about
2.3 V at 10 cm, 1.3 V at 20 cm, 0.4 V at 80 cm): ``V = K_V_CM / (d_cm + OFFSET_CM)``.
Nearer than 10 cm the voltage folds back towards 0 (a reading there is ambiguous, as on
the sensor); a new reading every 38 ms (the datasheet's measuring period)."""

import numpy as np

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.option_table import Num
from sim_plant.plant import Change
from sim_plant.sonars import Adc, AnalogRangeSonar, BeamRangeModel

K_V_CM = 33.9  # fits 2.3 V at 10 cm and 0.4 V at 80 cm
OFFSET_CM = 4.74
NEAR_CM = 10.0  # the voltage's peak; nearer, it folds back
FAR_M = 1.5  # beyond, the reading stays at the voltage of this range


def volts(range_m: float) -> float:
    """The output voltage for an object at ``range_m``."""
    d_cm = min(max(range_m, 0.0), FAR_M) * 100.0
    if d_cm < NEAR_CM:
        return K_V_CM / (NEAR_CM + OFFSET_CM) * d_cm / NEAR_CM
    return K_V_CM / (d_cm + OFFSET_CM)


class _Sharp(AnalogRangeSonar):
    """The analog sensor with the inverse law instead of a linear one."""

    def sample(self, t_us: int, plant, out: list) -> None:
        self.true_m, self.reading_m = self.model.measure(t_us, plant.pose_at(t_us), plant.world, plant.rng)
        self.value = self.adc.u16(volts(self.reading_m))
        out.append(Change(t_us, self.name, self.value))


class IrDistance(PartType):
    kind = "ir_distance"
    doc = "Sharp GP2Y0A21YK infrared distance sensor, 10-80 cm, on an ADC: volts fall as the inverse of the range."
    OPTIONS = (
        Opt("noise_sd_m", Num("metres", 0, 1), 0.005, "Gaussian range noise"),
        Opt(
            "period_us",
            Num("microseconds", 100, 1_000_000, whole=True),
            38_000,
            "a new reading every (datasheet: 38.3 ms)",
        ),
        Opt("adc_bits", Num("", 1, 16, whole=True), 12, "the board's ADC resolution"),
        Opt("adc_vref_v", Num("volts", 0.1, 50), 3.3, "the ADC's full scale"),
    )
    SIGNALS = (Sig("adc", "out", "u16", "the ADC reading (read_u16) of the output voltage"),)
    TRUTH = ("{name}_range_m", "{name}_reading_m")
    VIEWS = (
        View(
            "range",
            "the range the ADC reading says against the true range",
            signals=("adc",),
            truth=("{name}_range_m",),
        ),
    )
    needs_body = True

    def reading(self, suffix: str, values):
        """The range (m) a read_u16 value says, by the inverse law (beyond the fold)."""
        v = np.maximum(values / 65535 * self.options["adc_vref_v"], 1e-3)
        return np.clip((K_V_CM / v - OFFSET_CM) / 100.0, NEAR_CM / 100.0, FAR_M)

    def add(self, build: Build) -> None:
        o = self.options
        model = BeamRangeModel(self.mount_rad(), noise_sd_m=o["noise_sd_m"], min_m=0.0, max_m=FAR_M)
        sensor = _Sharp(
            f"{self.name}.adc",
            model,
            period_us=o["period_us"],
            phase_us=o["period_us"],
            adc=Adc(o["adc_bits"], o["adc_vref_v"]),
        )
        sensor.value = sensor.adc.u16(volts(FAR_M))
        build.parts.append(sensor)
