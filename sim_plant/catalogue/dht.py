"""Part ``dht``: a DHT22 (AM2302) or DHT11 temperature and humidity sensor on its one data
wire, answered at the frame level: the board's ``dht_readinto`` (``esp.dht_readinto``,
``rp2.dht_readinto``; MicroPython's drivers/dht/dht.c) pulls the line low 18 ms, lets it
go, and the sensor answers with 40 bits: humidity (2 bytes), temperature (2 bytes), a
checksum (their sum's low byte). The shim plays that read as one read of 5 bytes on the
pin's line, ``dht:<gpio>`` (``host/shim/_hildht.py``), at the instant the line is let go,
and moves the clock on by the reply's length as the bits it carries make it (80 + 80 us of
preamble, then 50 us low and 26 us (a 0) or 70 us (a 1) high a bit).

DHT22: humidity and temperature in tenths (0.1 % RH, 0.1 °C), a negative temperature with
bit 15 set. DHT11: whole numbers in the first byte of each pair (the second 0). Each is
clamped to the sensor's range (DHT11: 0..50 °C, 20..90 %). The values are the options'
(``temperature_c``, ``humidity_pct``), or what a scenario's set-control ``temperature`` /
``humidity`` set last, as Wokwi's sliders do. Not modelled: ``NOT_MODELLED`` (docs/parts.md)."""

from sim_plant.buses import BusDevice, BusName
from sim_plant.catalogue.base import Build, Opt, PartType
from sim_plant.controls import Control
from sim_plant.option_table import Num, OneOf

LINE_ADDRESS = 0x40  # (the one device on its line answers the shim's read here)
RANGES = {"dht22": ((-40.0, 80.0), (0.0, 100.0)), "dht11": ((0.0, 50.0), (20.0, 90.0))}


def frame(model: str, temperature_c: float, humidity_pct: float) -> bytes:
    """The 5 bytes the sensor sends for these values (checksum last)."""
    (t_lo, t_hi), (h_lo, h_hi) = RANGES[model]
    t = min(max(temperature_c, t_lo), t_hi)
    h = min(max(humidity_pct, h_lo), h_hi)
    if model == "dht22":
        hum = round(h * 10)
        temp = round(abs(t) * 10) | (0x8000 if t < 0 else 0)
        data = bytes((hum >> 8, hum & 0xFF, temp >> 8, temp & 0xFF))
    else:
        data = bytes((round(h), 0, round(t), 0))
    return data + bytes((sum(data) & 0xFF,))


class DhtChip(BusDevice):
    FIXED_STATE = (*BusDevice.FIXED_STATE, "model", "values")

    def __init__(self, name: str, line: str, model: str, values: tuple, controls=None):
        super().__init__(name, line, LINE_ADDRESS)
        self.model, self.values, self.controls = model, values, controls
        self.reply = b""
        self.reads = 0
        self.last = values

    def begin(self, t_us, reading):
        temperature_c, humidity_pct = self.values
        if self.controls is not None:
            temperature_c = self.controls.value_at(self.label, "temperature", t_us, temperature_c)
            humidity_pct = self.controls.value_at(self.label, "humidity", t_us, humidity_pct)
        self.last = (temperature_c, humidity_pct)
        self.reply = frame(self.model, temperature_c, humidity_pct)
        self.reads += 1

    def read(self, t_us):
        byte, self.reply = (self.reply[0], self.reply[1:]) if self.reply else (0xFF, b"")
        return byte

    def truth(self, t_us, plant) -> dict:
        return {
            f"{self.label}_reads": self.reads,
            f"{self.label}_temperature_c": self.last[0],
            f"{self.label}_humidity_pct": self.last[1],
        }


class Dht(PartType):
    kind = "dht"
    MODELLED_FEATURES = (
        "the 40-bit reply of a DHT22 or DHT11 to the board's dht_readinto, its checksum, the sensor's ranges",
        "the reply's time on the wire",
    )
    NOT_MODELLED = (
        "the 2 s (DHT22) or 1 s (DHT11) between conversions (a faster read gets a fresh value here, the "
        "previous one on a board)",
        "noise and accuracy",
        "the reply's edges on the pin (no probe sees them)",
    )
    doc = "A DHT22 or DHT11 temperature and humidity sensor on one data pin (MicroPython's dht module)."
    OPTIONS = (
        Opt("bus", BusName(), "dht:4", "its data line as the shim names it: dht:<the GPIO's number>"),
        Opt("model", OneOf(("dht22", "dht11")), "dht22", "the sensor (DHT22 = AM2302)"),
        Opt("temperature_c", Num("degrees C", -40, 80), 24.0, "what it measures (Wokwi's default: 24)"),
        Opt("humidity_pct", Num("percent RH", 0, 100), 40.0, "what it measures (Wokwi's default: 40)"),
    )
    SIGNALS = ()
    TRUTH = ("{name}_reads", "{name}_temperature_c", "{name}_humidity_pct")
    VIEWS = ()
    CONTROLS = (
        Control("temperature", Num("°C", -40, 80), "the temperature it measures from then on"),
        Control("humidity", Num("% RH", 0, 100), "the relative humidity it measures from then on"),
    )
    on_bus = True

    def check(self) -> None:
        if not self.options["bus"].startswith("dht:"):
            raise ValueError(f"bus: expected dht:<gpio> (its data line), got {self.options['bus']}")

    def add(self, build: Build) -> None:
        o = self.options
        values = (float(o["temperature_c"]), float(o["humidity_pct"]))
        build.parts.append(DhtChip(self.name, o["bus"], o["model"], values, build.controls))
