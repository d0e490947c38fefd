"""Part ``ranger_trigger``: the RX line of a chain of analog rangers (MaxBotix LV-EZ):
each time the board raises it, every ranger it names (``analog_ranger`` parts with
``triggered = true``, listed before it) takes one reading ``ranging_us`` later
(:class:`sim_plant.sonars.SonarRx`)."""

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.option_table import Name, Num, Rows
from sim_plant.sonars import SonarRx, TriggeredSonar


class RangerTrigger(PartType):
    kind = "ranger_trigger"
    doc = "The RX (trigger) line of a chain of analog rangers: a rising edge starts one ranging of each."
    OPTIONS = (
        Opt(
            "rangers",
            Rows(Name(), 16),
            [],
            "the triggered analog_ranger parts it starts, by name; empty: every one listed before it",
        ),
        Opt("ranging_us", Num("microseconds", 1, 1_000_000, whole=True), 49_000, "from the RX edge to the new reading"),
    )
    SIGNALS = (Sig("rx", "in", "level", "the RX line: a rising edge starts a ranging"),)
    TRUTH = ()
    VIEWS = (View("level", "the RX line over time", signals=("rx",)),)
    needs_body = True

    def add(self, build: Build) -> None:
        by_signal = {getattr(p, "name", None): p for p in build.parts if isinstance(p, TriggeredSonar)}
        if not self.options["rangers"]:
            build.parts.append(SonarRx(f"{self.name}.rx", list(by_signal.values()), self.options["ranging_us"]))
            return
        sonars = []
        for ranger in self.options["rangers"]:
            sonar = by_signal.get(f"{ranger}.adc")
            if sonar is None:
                raise ValueError(
                    f"rangers: {ranger!r} is not an analog_ranger with triggered = true listed before this part"
                )
            sonars.append(sonar)
        build.parts.append(SonarRx(f"{self.name}.rx", sonars, self.options["ranging_us"]))
