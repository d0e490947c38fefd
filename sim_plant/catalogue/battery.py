"""Part ``battery``: the battery's voltage through a resistor divider on an ADC pin,
draining at a fixed rate and with the motors' use (the wheels' mean speed as a share of
full speed, taken at each sample). Its ``voltage`` control sets the voltage at an instant
(the ADC reads it from then on), and it drains on from there."""

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.controls import Control
from sim_plant.engine import Part
from sim_plant.option_table import Name, Num
from sim_plant.plant import Change
from sim_plant.sonars import Adc


class _Cell(Part):
    """The battery's divided voltage, sampled every period. With ``shares`` the divider's
    line is a pin's too (the 3pi+ 2040's GP26, the down emitters' control): what the pin
    drives goes on to that chip's input; let go, the line is the divider's, under a logic
    high, so the chip's input reads low."""

    FIXED_STATE = ("inputs", "outputs", "controls", "shares", "targets")
    targets_option = "shares"  # (the option that names its targets, in the plant's check of them)

    def __init__(self, name: str, o: dict, controls=None):
        self.signal, self.label = f"{name}.adc", name
        self.controls = controls  # (the plant's timeline: a voltage set by the control)
        self.outputs = {self.signal: "u16"}
        self.shares = o["shares"]
        self.targets = () if self.shares is None else (self.shares,)  # (checked by the plant: another part's input)
        if self.shares is not None:
            self.inputs = {self.signal: "level"}
        self.v = float(o["full_v"])
        self.empty_v, self.ratio = float(o["empty_v"]), float(o["divider_ratio"])
        self.rate_v_s, self.motor_v_s = float(o["drain_v_per_s"]), float(o["motor_drain_v_per_s"])
        self.adc = Adc(o["adc_bits"], o["adc_vref_v"])
        self.period_us = int(o["period_us"])
        self.t_us = 0
        self.set_us = -1  # the instant of the last voltage set taken in
        self.next_us = self.period_us

    def initial_outputs(self) -> dict:
        return {self.signal: self.adc.u16(self.v * self.ratio)}

    def _load(self, plant) -> float:
        drive = plant.drive
        motors = getattr(drive, "motors", ())
        if not motors:
            return 0.0
        shares = [abs(w) / m.max_wheel_rad_s for w, m in zip(drive.wheel_rad_s, motors)]
        return min(1.0, sum(shares) / len(shares))

    def fire(self, t_us: int, plant, out: list) -> None:
        set_at = self.controls.last_set(self.label, "voltage", t_us) if self.controls is not None else None
        if set_at is not None and set_at[0] > self.set_us:  # (set since the last sample: it drains on from there)
            self.t_us, self.v, self.set_us = set_at[0], float(set_at[1]), set_at[0]
        dt_s = (t_us - self.t_us) * 1e-6
        self.v = max(self.empty_v, self.v - (self.rate_v_s + self.motor_v_s * self._load(plant)) * dt_s)
        self.t_us = t_us
        out.append(Change(t_us, self.signal, self.adc.u16(self.v * self.ratio)))
        self.next_us = t_us + self.period_us

    def set_input(self, name: str, value, t_us: int, plant) -> bool:
        # (the pin's drive, or -1 as it lets the line go: the divider's voltage, a logic low)
        plant.set_input(self.shares, 0 if value is None or value < 0 else (1 if value else 0))
        return False

    def truth(self, t_us: int, plant) -> dict:
        return {f"{self.label}_v": self.v}


class Battery(PartType):
    kind = "battery"
    doc = "The battery's voltage through a divider on an ADC, draining at a fixed rate and with motor use."
    OPTIONS = (
        Opt("full_v", Num("volts", 0.5, 100), 8.4, "the voltage at the start (2S Li-ion full)"),
        Opt("empty_v", Num("volts", 0, 100), 6.0, "it drains no lower"),
        Opt("divider_ratio", Num("fraction", 0, 1, above=True), 1 / 3, "ADC volts per battery volt (R2 / (R1 + R2))"),
        Opt("drain_v_per_s", Num("volts per second", 0, 10), 0.0, "fixed drain"),
        Opt("motor_drain_v_per_s", Num("volts per second", 0, 10), 0.0, "extra drain with the motors at full speed"),
        Opt("period_us", Num("microseconds", 100, 1_000_000_000, whole=True), 100_000, "a new sample every"),
        Opt("adc_bits", Num("", 1, 16, whole=True), 12, "the board's ADC resolution"),
        Opt("adc_vref_v", Num("volts", 0.1, 50), 3.3, "the ADC's full scale"),
        Opt(
            "shares",
            Name(),
            None,
            "a chip's input on the divider's line (the 3pi+ 2040's GP26, the down emitters' control: "
            "line.emitter): what the pin drives goes on to it; let go, the line is the divider's (a logic low there)",
        ),
    )
    SIGNALS = (
        Sig(
            "adc",
            "out",
            "u16",
            "the divided voltage's ADC reading (read_u16); with shares set it is io: a pin drives the line in turn",
        ),
    )
    TRUTH = ("{name}_v",)
    CONTROLS = (
        Control("voltage", Num("volts", 0, 100), "the battery's voltage from then on (it drains on from there)"),
    )
    VIEWS = (
        View("voltage", "the voltage the firmware read against the battery's", signals=("adc",), truth=("{name}_v",)),
    )

    def check(self) -> None:
        if self.options["empty_v"] > self.options["full_v"]:
            raise ValueError(
                f"empty_v: expected at most full_v ({self.options['full_v']}), got {self.options['empty_v']}"
            )

    def signals(self) -> dict[str, tuple[str, str]]:
        signals = super().signals()
        if self.options["shares"] is not None:
            signals[f"{self.name}.adc"] = ("io", "u16")
        return signals

    def control_change(self, control: str, value) -> tuple | None:
        super().control_change(control, value)
        o = self.options
        return f"{self.name}.adc", Adc(o["adc_bits"], o["adc_vref_v"]).u16(float(value) * o["divider_ratio"])

    def reading(self, suffix: str, values):
        """The battery's voltage a read_u16 value says, through the divider."""
        return values / 65535 * self.options["adc_vref_v"] / self.options["divider_ratio"]

    def add(self, build: Build) -> None:
        build.parts.append(_Cell(self.name, self.options, build.controls))
