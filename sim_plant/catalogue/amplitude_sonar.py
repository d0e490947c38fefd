"""Part ``amplitude_sonar``: an ultrasonic pair whose received amplitude, peak-held and
read by an ADC, falls with the range to the wall it looks at squarely (seed 002's duct
sonars, :mod:`sim_plant.physics.amplitude_sonar`). A robot's amplitude sonars share one ADC and
one update: the first such part makes the array, each further one adds its channel, and
the shared options (all but ``gain``) must then be the same on every one of them."""

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.option_table import GAIN, Num, length
from sim_plant.physics.amplitude_sonar import AmplitudeChannel, AmplitudeSonarArray
from sim_plant.sonars import Adc

SHARED = (
    "noise_sd_v",
    "corner_spike_p",
    "min_range_m",
    "max_range_m",
    "discharge_time_constant_ms",
    "period_us",
    "adc_bits",
    "adc_vref_v",
)


class AmplitudeSonar(PartType):
    kind = "amplitude_sonar"
    doc = "An amplitude sonar: peak-held echo amplitude on an ADC, falling with the range to a square-on wall."
    OPTIONS = (
        Opt("gain", GAIN, 1.0, "this channel's gain (component spread the firmware calibrates)"),
        Opt("noise_sd_v", Num("volts", 0, 10), 0.01, "Gaussian noise on the held voltage (shared)"),
        Opt("corner_spike_p", Num("probability", 0, 1), 0.01, "chance an update sees a corner in the cone (shared)"),
        Opt("min_range_m", length(0.001, 10), 0.030, "range of the full-scale echo (shared)"),
        Opt("max_range_m", length(0.01, 100), 1.0, "farthest wall it hears (shared)"),
        Opt("discharge_time_constant_ms", Num("milliseconds", 0, 100_000), 150.0, "the peak detector's decay (shared)"),
        Opt("period_us", Num("microseconds", 100, 1_000_000_000, whole=True), 25_000, "an update every (shared)"),
        Opt("adc_bits", Num("", 1, 16, whole=True), 8, "the ADC's resolution (shared)"),
        Opt("adc_vref_v", Num("volts", 0.1, 50), 5.0, "the ADC's full scale (shared)"),
    )
    SIGNALS = (Sig("adc", "out", "u16", "the ADC reading (read_u16)"),)
    TRUTH = ("{name}_range_m",)
    VIEWS = (View("range", "the ADC reading against the true range to the wall", ("adc",), TRUTH),)
    needs_body = True

    def check(self) -> None:
        near_m, far_m = self.options["min_range_m"], self.options["max_range_m"]
        if near_m >= far_m:
            raise ValueError(f"min_range_m: expected less than max_range_m ({far_m}), got {near_m}")

    def add(self, build: Build) -> None:
        o = self.options
        channel = AmplitudeChannel(f"{self.name}.adc", self.mount_rad(), o["gain"])
        array = next((p for p in build.parts if isinstance(p, AmplitudeSonarArray)), None)
        if array is None:
            array = AmplitudeSonarArray(
                [],
                noise_v=o["noise_sd_v"],
                corner_spike_p=o["corner_spike_p"],
                min_range_m=o["min_range_m"],
                max_range_m=o["max_range_m"],
                discharge_tau_ms=o["discharge_time_constant_ms"],
                update_us=o["period_us"],
                adc=Adc(o["adc_bits"], o["adc_vref_v"]),
            )
            array.shared_options = {k: o[k] for k in SHARED}
            build.parts.append(array)
        else:
            for key, value in array.shared_options.items():
                if o[key] != value:
                    raise ValueError(f"{key}: the amplitude sonars share it, expected {value} as before, got {o[key]}")
        array.channels.append(channel)
        array.outputs[channel.name] = "u16"
