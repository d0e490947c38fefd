"""Part ``buzzer``: a passive piezo buzzer on a board output (``<name>.in``): it sounds
while a PWM with a duty between 0 and full drives it, at the PWM's frequency; a steady
level (a plain pin, a duty of 0 or of 65535) is silence (a piezo clicks, no tone). The
part records each tone (its frequency, its start and end), and the truth has the tone now
(``<name>_freq_hz``, 0: silent) and how many tones began. No sound, no loudness: a
duty's share changes nothing but silence at 0 and full."""

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.engine import Part
from sim_plant.option_table import Num

FULL = 65535


class _Buzzer(Part):
    FIXED_STATE = ("inputs", "outputs", "max_tones")

    def __init__(self, name: str, max_tones: int):
        self.label, self.max_tones = name, max_tones
        self.inputs = {f"{name}.in": "pwm"}
        self.outputs = {}
        self.freq_hz = 0
        self.tones: list = []  # [t_start_us, t_end_us or None, freq_hz]
        self.started = 0

    def _sound(self, t_us: int, freq_hz: int) -> None:
        if freq_hz == self.freq_hz:
            return
        if self.tones and self.tones[-1][1] is None:
            self.tones[-1][1] = t_us
        self.freq_hz = freq_hz
        if freq_hz:
            self.started += 1
            if len(self.tones) >= self.max_tones:
                self.tones.pop(0)
            self.tones.append([t_us, None, freq_hz])

    def set_input(self, name: str, value, t_us: int, plant) -> bool:
        self._sound(t_us, 0)  # a level: no tone
        return False

    def set_pwm(self, name: str, freq_hz: int, duty_u16: int, t_us: int) -> None:
        self._sound(t_us, int(freq_hz) if 0 < duty_u16 < FULL else 0)

    def truth(self, t_us: int, plant) -> dict:
        return {f"{self.label}_freq_hz": self.freq_hz, f"{self.label}_tones": self.started}


class Buzzer(PartType):
    kind = "buzzer"
    doc = "A passive piezo buzzer on a PWM output: the tones it plays (frequency, start, end)."
    OPTIONS = (Opt("max_tones", Num("", 1, 100_000, whole=True), 1000, "tones kept (then the oldest goes)"),)
    SIGNALS = (Sig("in", "in", "pwm", "what the board drives: a PWM (a tone) or a level (silence)"),)
    TRUTH = ("{name}_freq_hz", "{name}_tones")
    VIEWS = (View("level", "the drive and the tone over time", signals=("in",), truth=("{name}_freq_hz",)),)

    def add(self, build: Build) -> None:
        build.parts.append(_Buzzer(self.name, self.options["max_tones"]))
