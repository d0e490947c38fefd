"""Part ``echo_sounder``: a depth sounder's transducer looking sideways at a wall (the
NAVMAN 100 of seeds 000/001, :class:`sim_plant.physics.echo_sounder.NavmanSideSounder`), either
talking NMEA 0183 ``$SDDPT`` on a UART (with two transducers, one at the mount and one
mirrored across the body's centre line, chosen by a select line), or as an analog
output on an ADC (volts per metre; 0 V for no reading). Fault windows make readings
wrong, missing, or (NMEA) no sentence at all."""

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.option_table import TIME, Num, OneOf, Row, Rows, length
from sim_plant.physics.echo_sounder import NavmanSideSounder, NmeaDepthSounder
from sim_plant.pool import ADC_V_PER_M
from sim_plant.sonars import Adc, AnalogRangeSonar

NMEA = (("output", ("nmea",)),)
FAULT = Row((TIME, TIME, OneOf(("wrong", "none", "silent"))), "[t0_s, t1_s, kind]")


class EchoSounder(PartType):
    kind = "echo_sounder"
    doc = "A depth sounder used sideways: NMEA $SDDPT on a UART (one or two transducers), or an analog output."
    OPTIONS = (
        Opt("output", OneOf(("nmea", "adc")), "nmea", "NMEA sentences on a UART, or volts on an ADC"),
        Opt("transducers", OneOf((1, 2)), 1, "NMEA: 2 adds one mirrored across the body, chosen by the select line"),
        Opt("period_us", Num("microseconds", 100, 1_000_000_000, whole=True), 500_000, "a new reading every"),
        Opt("phase_us", Num("microseconds", 1, 1_000_000_000, whole=True), 100_000, "the first reading at"),
        Opt("noise_sd_m", length(0, 10), 0.1, "Gaussian range noise"),
        Opt(
            "bytes_per_change", Num("", 0, 4096, whole=True), 1, "NMEA: bytes the UART delivers at once (0: a sentence)"
        ),
        Opt("switch_settle_s", Num("seconds", 0, 3600), 0.0, "NMEA: extra noise this long after a select change"),
        Opt("volts_per_m", Num("volts per metre", 0, 100, above=True), ADC_V_PER_M, "ADC: the output's slope"),
        Opt("adc_bits", Num("", 1, 16, whole=True), 12, "ADC: the board's resolution"),
        Opt("adc_vref_v", Num("volts", 0.1, 50), 3.3, "ADC: the full scale"),
        Opt("faults", Rows(FAULT, 1000), [], "windows of wrong or missing (none) readings, or no sentence (silent)"),
    )
    SIGNALS = (
        Sig("uart", "out", "bytes", "NMEA $SDDPT sentences, 4800 baud", NMEA),
        Sig(
            "select",
            "in",
            "level",
            "0: the transducer at the mount, 1: the mirrored one",
            (*NMEA, ("transducers", (2,))),
        ),
        Sig("adc", "out", "u16", "the ADC reading (read_u16)", (("output", ("adc",)),)),
    )
    TRUTH = ("{name}_reading_m",)
    VIEWS = (View("range", "the range the sounder reported against the true range", ("uart", "adc"), TRUTH),)
    needs_body = True

    def check(self) -> None:
        if self.options["output"] == "adc" and self.options["transducers"] != 1:
            raise ValueError("transducers: an ADC output has one transducer (a second is a second part)")

    def add(self, build: Build) -> None:
        o = self.options
        faults = [(float(t0), float(t1), kind) for t0, t1, kind in o["faults"]]
        silent = [(t0, t1) for t0, t1, kind in faults if kind == "silent"]
        faults = [f for f in faults if f[2] != "silent"]
        x, y, heading = self.mount_rad()
        mounts = [(x, y, heading), (x, -y, -heading)][: o["transducers"]]
        if o["output"] == "adc":  # an analog output cannot fall silent: it reads 0 V
            model = NavmanSideSounder(
                mounts[0], noise_sd_m=o["noise_sd_m"], faults=faults + [(*w, "none") for w in silent]
            )
            adc = Adc(o["adc_bits"], o["adc_vref_v"])
            timing = {"period_us": o["period_us"], "phase_us": o["phase_us"]}
            build.parts.append(
                AnalogRangeSonar(f"{self.name}.adc", model, adc=adc, volts_per_m=o["volts_per_m"], **timing)
            )
            return
        build.parts.append(
            NmeaDepthSounder(
                f"{self.name}.uart",
                [NavmanSideSounder(m, noise_sd_m=o["noise_sd_m"], faults=faults) for m in mounts],
                select=f"{self.name}.select" if o["transducers"] == 2 else None,
                period_us=o["period_us"],
                phase_us=o["phase_us"],
                bytes_per_change=o["bytes_per_change"],
                switch_settle_s=o["switch_settle_s"],
                silent=silent,
            )
        )
