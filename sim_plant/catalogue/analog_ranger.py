"""Part ``analog_ranger``: an ultrasonic ranger with an analog output (MaxBotix LV-EZ
style, Vcc/512 per inch) on an ADC pin, a new sample every ``period_us``
(:mod:`sim_plant.sonars`), or once each time a ``ranger_trigger`` line rises."""

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.option_table import Flag, Num
from sim_plant.sonars import MAXBOTIX_V_PER_M, Adc, AnalogRangeSonar, BeamRangeModel, TriggeredSonar


class AnalogRanger(PartType):
    kind = "analog_ranger"
    doc = "An analog ultrasonic ranger (MaxBotix LV-EZ style) on an ADC: volts proportional to range."
    OPTIONS = (
        Opt("noise_sd_m", Num("metres", 0, 10), 0.003, "Gaussian range noise"),
        Opt("min_range_m", Num("metres", 0, 100), 0.15, "nearest range it reports (nearer reads this)"),
        Opt("max_range_m", Num("metres", 0, 100, above=True), 6.45, "farthest range (nothing in view reads this)"),
        Opt(
            "volts_per_m", Num("volts per metre", 0, 100, above=True), round(MAXBOTIX_V_PER_M, 4), "the output's slope"
        ),
        Opt("period_us", Num("microseconds", 100, 1_000_000_000, whole=True), 50_000, "a new sample every"),
        Opt(
            "phase_us",
            Num("microseconds", 0, 1_000_000_000, whole=True, none=True),
            None,
            "the first sample's time; unset: one period in",
        ),
        Opt("adc_bits", Num("", 1, 16, whole=True), 12, "the board's ADC resolution"),
        Opt("adc_vref_v", Num("volts", 0.1, 50), 3.3, "the ADC's full scale"),
        Opt(
            "triggered",
            Flag(),
            False,
            "true: it ranges only when a ranger_trigger part's line rises (no sample every period_us)",
        ),
    )
    SIGNALS = (Sig("adc", "out", "u16", "the ADC reading (read_u16)"),)
    TRUTH = ("{name}_range_m", "{name}_reading_m")
    VIEWS = (
        View(
            "range",
            "the range the ADC reading says against the true range",
            signals=("adc",),
            truth=("{name}_range_m", "{name}_reading_m"),
        ),
    )
    needs_body = True

    def check(self) -> None:
        near_m, far_m = self.options["min_range_m"], self.options["max_range_m"]
        if near_m >= far_m:
            raise ValueError(f"min_range_m: expected less than max_range_m ({far_m}), got {near_m}")

    def reading(self, suffix: str, values):
        """The range (m) a read_u16 value says, through the output's slope."""
        return values / 65535 * self.options["adc_vref_v"] / self.options["volts_per_m"]

    def add(self, build: Build) -> None:
        o = self.options
        model = BeamRangeModel(
            self.mount_rad(), noise_sd_m=o["noise_sd_m"], min_m=o["min_range_m"], max_m=o["max_range_m"]
        )
        sonar_cls = TriggeredSonar if o["triggered"] else AnalogRangeSonar
        build.parts.append(
            sonar_cls(
                f"{self.name}.adc",
                model,
                period_us=o["period_us"],
                phase_us=o["period_us"] if o["phase_us"] is None else o["phase_us"],
                volts_per_m=o["volts_per_m"],
                adc=Adc(o["adc_bits"], o["adc_vref_v"]),
            )
        )
