"""The part table: each Wokwi part type we map, the catalogue part it becomes (named by
the diagram's ``id``), what its attributes become (options, with units), which attributes
only draw it, and what differs from Wokwi; and the types we refuse, with why.
``docs/wokwi.md``'s table is checked against this one (``host/tests/test_wokwi_parts.py``).

A mapper gets the part, the diagram (its nets) and the project's context (the firmware's
PWM pins and buses, read from its code) and returns a :class:`Mapped`: the
``[[plant.parts]]`` entry, the board pins it uses and their wiring, and the comments the
written rig file carries."""

import difflib
import math
from dataclasses import dataclass, field
from typing import Callable

from host.core.errors import ConfigError
from host.rig.config.wokwi.boards import GND

LANE_M = 1.5  # HC-SR04s on a desk: one lane each, this far apart (the cone at 4 m is 1.05 m wide)
MAX_SONARS = 6  # lanes within the mount's +-10 m
DESK_X_M = 1.0  # where the desk stands in its room (x), the sonars looking along +x
SONAR_BOX_M = (0.1, 1.2)  # each lane's target: depth, width
SONAR_MAX_RANGE_M = 4.5  # Wokwi's 400 cm must still be read


@dataclass
class Context:
    """What a mapper needs beyond its part: the diagram, the chip family, the GPIOs the
    code drives with PWM, the buses the code makes, and the desk's HC-SR04 lanes so far."""

    diagram: object
    family: str
    pwm_pins: set = field(default_factory=set)
    buses: dict = field(default_factory=dict)
    sonars: list = field(default_factory=list)  # (part id, distance_m)


@dataclass
class Mapped:
    """One part's share of the rig: its ``[[plant.parts]]`` entry (None: it adds no part,
    a logic analyser), the board pins (key -> GPIO) and their wiring, and comments."""

    entry: dict | None
    pins: dict = field(default_factory=dict)
    wiring: dict = field(default_factory=dict)
    notes: list = field(default_factory=list)


@dataclass(frozen=True)
class PartMap:
    """A Wokwi part type we map: to our ``kind``; ``attrs`` (attribute -> what it becomes),
    ``cosmetic`` (attributes that only draw it), ``differs`` (docs), ``build``."""

    wokwi: str
    kind: str
    attrs: dict
    cosmetic: tuple
    differs: str
    build: Callable


# -- helpers ---------------------------------------------------------------------------------


def _error(part, message: str) -> ConfigError:
    return ConfigError(f"diagram.json: {part.where()}: {message}")


def number(part, name: str, default: float, lo: float, hi: float, unit: str) -> float:
    """Attribute ``name`` as a number (Wokwi writes them as text: ``"500"``, ``"0x3c"``)."""
    raw = part.attrs.get(name, default)
    try:
        value = float(int(raw, 0)) if isinstance(raw, str) and raw.lower().startswith("0x") else float(raw)
    except (TypeError, ValueError):
        value = math.nan
    if not (math.isfinite(value) and lo <= value <= hi):
        raise _error(part, f"attrs.{name}: expected a number {unit}from {lo:g} to {hi:g}, got {raw!r}")
    return value


def choice(part, name: str, default: str, values: tuple) -> str:
    raw = str(part.attrs.get(name, default))
    if raw not in values:
        raise _error(part, f"attrs.{name}: expected one of {', '.join(map(repr, values))}, got {raw!r}")
    return raw


def wire(mapped: Mapped, ctx: Context, part, pin: str, signal: str, required: bool = True) -> int | None:
    """Wire the board pin on ``part:pin``'s net to ``signal``; the GPIO, or None."""
    found = ctx.diagram.gpio(f"{part.id}:{pin}")
    if found is None:
        if required:
            raise _error(part, f"pin {pin} is wired to no GPIO of the board: expected one (its signal {signal})")
        return None
    key, gpio = found
    if key in mapped.wiring:
        raise _error(part, f"pin {pin}: {key} is wired twice")
    mapped.pins[key] = gpio
    mapped.wiring[key] = signal
    return gpio


def supply_v(ctx: Context, part, pin: str, mapped: Mapped) -> float:
    level = ctx.diagram.rail(f"{part.id}:{pin}")
    if level in (None, GND):
        mapped.notes.append(f"{part.id}:{pin} is not on a supply pin: taken as 3.3 V")
        return 3.3
    return level


def entry(part, kind: str, **options) -> dict:
    return {"kind": kind, "name": part.id, **options}


# -- mappers ---------------------------------------------------------------------------------


def button(part, ctx: Context) -> Mapped:
    m = Mapped(None)
    for side, other in (("1.l", "2.l"), ("2.l", "1.l")):
        if ctx.diagram.gpio(f"{part.id}:{side}") is not None:
            wire(m, ctx, part, side, f"{part.id}.out")
            level = ctx.diagram.rail(f"{part.id}:{other}")
            if level is None:
                raise _error(part, f"pin {other} is on no ground or supply pin: a press would change nothing")
            bounce = choice(part, "bounce", "", ("", "0", "1"))
            m.entry = entry(part, "button", active_low=level == GND)
            m.notes.append(f"pressed: reads {0 if level == GND else 1}; no bounce (Wokwi's default bounce={bounce!r})")
            return m
    raise _error(part, "neither contact (1.l/1.r, 2.l/2.r) is wired to a GPIO of the board")


def slide_switch(part, ctx: Context) -> Mapped:
    m = Mapped(None)
    wire(m, ctx, part, "2", f"{part.id}.out")
    levels = {}
    for pin, side in (("1", "left"), ("3", "right")):
        level = ctx.diagram.rail(f"{part.id}:{pin}")
        levels[f"{side}_level"] = 0 if level == GND else 1
        if level is None:
            m.notes.append(f"{part.id}:{pin} is open: read as 1 (the pin's pull-up)")
    position = "right" if choice(part, "value", "", ("", "0", "1")) == "1" else "left"
    choice(part, "bounce", "", ("", "0", "1"))
    m.entry = entry(part, "slide_switch", position=position, **levels)
    return m


def led(part, ctx: Context) -> Mapped:
    m = Mapped(None)
    for pin, lit in (("A", "high"), ("C", "low")):
        if ctx.diagram.gpio(f"{part.id}:{pin}") is not None:
            gpio = wire(m, ctx, part, pin, f"{part.id}.in")
            signal = "duty" if gpio in ctx.pwm_pins else "level"
            m.entry = entry(part, "probe", signal=signal)
            m.notes.append(f"lit when the pin is {lit}" + (" (a PWM: its duty recorded)" if signal == "duty" else ""))
            return m
    m.notes.append("left out: neither A nor C is on a GPIO (a power LED)")
    return m


def rgb_led(part, ctx: Context) -> Mapped:
    m = Mapped(None)
    gpios = [wire(m, ctx, part, c, f"{part.id}.{c.lower()}", required=False) for c in "RGB"]
    if not any(g is not None for g in gpios):
        raise _error(part, "none of R, G, B is wired to a GPIO of the board")
    common = choice(part, "common", "anode", ("anode", "cathode"))
    signal = "duty" if any(g in ctx.pwm_pins for g in gpios if g is not None) else "level"
    m.entry = entry(part, "rgb_led", common=common, signal=signal)
    return m


def potentiometer(part, ctx: Context) -> Mapped:
    m = Mapped(None)
    wire(m, ctx, part, "SIG", f"{part.id}.sig")
    value = number(part, "value", 0, 0, 1023, "")
    m.entry = entry(part, "potentiometer", position=round(value / 1023, 6))
    return m


def photoresistor(part, ctx: Context) -> Mapped:
    m = Mapped(None)
    ao = wire(m, ctx, part, "AO", f"{part.id}.ao", required=False)
    do = wire(m, ctx, part, "DO", f"{part.id}.do", required=False)
    if ao is None and do is None:
        raise _error(part, "neither AO nor DO is wired to a GPIO of the board")
    m.entry = entry(
        part,
        "photoresistor",
        lux=number(part, "lux", 500, 0.01, 200_000, "of lux "),
        rl10_kohm=number(part, "rl10", 50, 0.1, 10_000, "of kilo-ohms "),
        gamma=number(part, "gamma", 0.7, 0.1, 2, ""),
        threshold_v=number(part, "threshold", 2.5, 0, 50, "of volts "),
    )
    m.entry["supply_v"] = supply_v(ctx, part, "VCC", m)
    return m


def hc_sr04(part, ctx: Context) -> Mapped:
    m = Mapped(None)
    wire(m, ctx, part, "TRIG", f"{part.id}.trig")
    wire(m, ctx, part, "ECHO", f"{part.id}.echo")
    distance_cm = number(part, "distance", 400, 2, 400, "of centimetres ")
    lane = len(ctx.sonars)
    if lane >= MAX_SONARS:
        raise _error(part, f"more than {MAX_SONARS} HC-SR04s on one diagram: expected at most {MAX_SONARS}")
    ctx.sonars.append((part.id, distance_cm / 100))
    m.entry = entry(part, "hcsr04", noise_sd_m=0.0, max_range_m=SONAR_MAX_RANGE_M)
    m.entry["mount"] = {"x_m": 0.0, "y_m": lane * LANE_M, "heading_deg": 0.0}
    m.notes.append(f"a box {distance_cm:g} cm in front of it on the desk (Wokwi's distance)")
    return m


def servo(part, ctx: Context) -> Mapped:
    m = Mapped(None)
    wire(m, ctx, part, "PWM", f"{part.id}.pwm")
    m.entry = entry(part, "servo", start_deg=0.0)
    m.notes.append("0 to 180 degrees between 500 and 2500 us pulses; at 0 degrees at reset, as Wokwi's")
    return m


def relay(part, ctx: Context) -> Mapped:
    m = Mapped(None)
    wire(m, ctx, part, "IN", f"{part.id}.in")
    transistor = choice(part, "transistor", "npn", ("npn", "pnp"))
    m.entry = entry(part, "relay", active_low=transistor == "pnp")
    m.notes.append("its contacts (NO, NC, COM) switch nothing here: the truth says when they close")
    return m


def _strip(part, ctx: Context, count: int) -> Mapped:
    m = Mapped(None)
    if ctx.diagram.gpio(f"{part.id}:DIN") is None:
        raise _error(part, "DIN is wired to no GPIO of the board (a chain of strips is not mapped: one strip a pin)")
    wire(m, ctx, part, "DIN", f"{part.id}.din")
    m.entry = entry(part, "ws2812_strip", count=count)
    return m


def neopixel(part, ctx: Context) -> Mapped:
    return _strip(part, ctx, 1)


def led_ring(part, ctx: Context) -> Mapped:
    return _strip(part, ctx, int(number(part, "pixels", 16, 1, 256, "of LEDs ")))


def neopixel_matrix(part, ctx: Context) -> Mapped:
    rows = int(number(part, "rows", 8, 1, 256, "of rows "))
    cols = int(number(part, "cols", 8, 1, 256, "of columns "))
    if rows * cols > 256:
        raise _error(part, f"{rows} x {cols} LEDs: expected at most 256 (the ws2812_strip's most)")
    return _strip(part, ctx, rows * cols)


def i2c_bus(part, ctx: Context, m: Mapped) -> str:
    """The bus the chip's SDA and SCL are on, as the firmware names it (``docs/wokwi.md``)."""
    pins = {}
    for pin in ("SCL", "SDA"):
        found = ctx.diagram.gpio(f"{part.id}:{pin}")
        if found is None:
            raise _error(part, f"pin {pin} is wired to no GPIO of the board")
        pins[pin] = found[1]
    soft = f"i2c:{pins['SCL']},{pins['SDA']}"
    hardware = sorted(b for b in ctx.buses if b[:3] == "i2c" and b[3:].isdigit())
    if soft in ctx.buses:
        return soft
    if len(hardware) == 1:
        return hardware[0]
    if ctx.family == "rpi_pico":  # the RP2040's I2C block is fixed by the pins
        return f"i2c{pins['SDA'] // 2 % 2}"
    m.notes.append(f"bus i2c0 (the code's bus could not be read: {', '.join(hardware) or 'none found'})")
    return "i2c0"


def mpu6050(part, ctx: Context) -> Mapped:
    m = Mapped(None)
    bus = i2c_bus(part, ctx, m)
    address = 0x69 if ctx.diagram.rail(f"{part.id}:AD0") not in (None, GND) else 0x68
    wire(m, ctx, part, "INT", f"{part.id}.int", required=False)
    at_rest = {"accelX": 0, "accelY": 0, "accelZ": 1}
    for name, value in at_rest.items():
        if number(part, name, value, -16, 16, "of g ") != value:
            raise _error(
                part,
                f"attrs.{name}: only {value} g is modelled (a still board reads 0, 0, 1 g); got {part.attrs[name]!r}",
            )
    bias = [number(part, f"rotation{axis}", 0, -100, 100, "of deg/s ") for axis in "XYZ"]
    if number(part, "temperature", 25, -40, 85, "of degrees C ") != 25:
        raise _error(part, f"attrs.temperature: the chip reads 25 degrees C; got {part.attrs['temperature']!r}")
    m.entry = entry(
        part, "mpu6050", bus=bus, address=address, gyro_bias_dps=bias, gyro_noise_dps=0.0, accel_noise_m_s2=0.0
    )
    return m


def ssd1306(part, ctx: Context) -> Mapped:
    m = Mapped(None)
    bus = i2c_bus(part, ctx, m)
    address = int(number(part, "i2cAddress", 0x3C, 0x3C, 0x3D, ""))
    m.entry = entry(part, "ssd1306", bus=bus, address=address)
    m.notes.append(f"its pictures: {part.id}.png and {part.id}.gif in the trace folder")
    return m


def dht(part, ctx: Context) -> Mapped:
    m = Mapped(None)
    found = ctx.diagram.gpio(f"{part.id}:SDA")
    if found is None:
        raise _error(part, "pin SDA is wired to no GPIO of the board: expected one (its data line)")
    model = "dht11" if part.type == "wokwi-dht11" else "dht22"
    (t_lo, t_hi), (h_lo, h_hi) = {"dht22": ((-40, 80), (0, 100)), "dht11": ((0, 50), (20, 90))}[model]
    temperature = number(part, "temperature", 24, t_lo, t_hi, "of degrees C ")
    humidity = number(part, "humidity", 40, h_lo, h_hi, "of percent ")
    m.entry = entry(part, "dht", bus=f"dht:{found[1]}", model=model, temperature_c=temperature, humidity_pct=humidity)
    m.notes.append("read by the dht module a frame at a time (the line dht:<gpio>); set-control temperature, humidity")
    return m


def char_lcd(part, ctx: Context, cols: int, rows: int) -> Mapped:
    m = Mapped(None)
    if choice(part, "pins", "full", ("full", "i2c")) != "i2c":
        raise _error(
            part, 'attrs.pins: only "i2c" (the PCF8574 backpack) is mapped; the parallel pins ("full") are not'
        )
    bus = i2c_bus(part, ctx, m)
    address = int(number(part, "i2cAddress", 0x27, 0x08, 0x77, ""))
    m.entry = entry(part, "char_lcd", bus=bus, address=address, cols=cols, rows=rows)
    m.notes.append(f"{cols} x {rows} characters; the text it shows is in the part's screens")
    return m


def lcd1602(part, ctx: Context) -> Mapped:
    return char_lcd(part, ctx, 16, 2)


def lcd2004(part, ctx: Context) -> Mapped:
    return char_lcd(part, ctx, 20, 4)


def buzzer(part, ctx: Context) -> Mapped:
    m = Mapped(None)
    wire(m, ctx, part, "2", f"{part.id}.in")
    if ctx.diagram.rail(f"{part.id}:1") != GND:
        m.notes.append(f"{part.id}:1 is not on ground: taken as if it were")
    choice(part, "mode", "smooth", ("smooth", "accurate"))
    number(part, "volume", 1.0, 0.01, 1.0, "")
    m.entry = entry(part, "buzzer")
    m.notes.append("its tones (frequency, start, end) are recorded; no sound (mode and volume change nothing)")
    return m


def ky040(part, ctx: Context) -> Mapped:
    m = Mapped(None)
    wire(m, ctx, part, "CLK", f"{part.id}.clk")
    wire(m, ctx, part, "DT", f"{part.id}.dt")
    wire(m, ctx, part, "SW", f"{part.id}.sw", required=False)
    m.entry = entry(part, "rotary_knob")
    m.notes.append("turned by `turns` ([t_s, detents]) and pressed by `presses` (or a scenario's set-control pressed)")
    return m


def logic_analyzer(part, ctx: Context) -> Mapped:
    m = Mapped(None)
    for n in range(8):
        wire(m, ctx, part, f"D{n}", f"probe:{part.id}_D{n}", required=False)
    m.notes.append("each channel a probe: the trace's VCD has it")
    return m


def resistor(part, ctx: Context) -> Mapped:
    return Mapped(None)


LOOKS = ("color", "label", "flip", "xray")  # attributes that draw a part
TABLE = {
    p.wokwi: p
    for p in (
        PartMap(
            "wokwi-pushbutton",
            "button",
            {"bounce": "none: no bounce here (bounce_us = 0) whatever it says"},
            (*LOOKS, "key"),
            "pressed by `presses` (or a scenario's set-control), not by a click; no contact bounce unless `bounce_us`",
            button,
        ),
        PartMap(
            "wokwi-pushbutton-6mm",
            "button",
            {"bounce": "as wokwi-pushbutton"},
            (*LOOKS, "key"),
            "as wokwi-pushbutton",
            button,
        ),
        PartMap(
            "wokwi-slide-switch",
            "slide_switch",
            {"value": '`position` ("1": right)', "bounce": "none"},
            LOOKS,
            "pins 1 and 3 tied to ground read 0, to a supply 1, open 1 (the pull-up); no bounce",
            slide_switch,
        ),
        PartMap(
            "wokwi-led",
            "probe",
            {},
            (*LOOKS, "lightColor", "gamma", "brightness"),
            "recorded as the pin's level (or PWM duty): no light, no current",
            led,
        ),
        PartMap(
            "wokwi-rgb-led",
            "rgb_led",
            {"common": "`common` (anode by default, as Wokwi's)"},
            LOOKS,
            "its colour is in the truth (`<id>_rgb`), from levels or PWM duties",
            rgb_led,
        ),
        PartMap(
            "wokwi-potentiometer",
            "potentiometer",
            {"value": "`position` = value / 1023 (0 by default)"},
            LOOKS,
            "a fixed reading (a scenario turns it); as Wokwi's, value / 1023 of the ADC's full scale whatever VCC is",
            potentiometer,
        ),
        PartMap(
            "wokwi-slide-potentiometer",
            "potentiometer",
            {"value": "`position` = value / 1023"},
            (*LOOKS, "travelLength"),
            "as wokwi-potentiometer",
            potentiometer,
        ),
        PartMap(
            "wokwi-photoresistor-sensor",
            "photoresistor",
            {
                "lux": "`lux`",
                "rl10": "`rl10_kohm` (kilo-ohms)",
                "gamma": "`gamma`",
                "threshold": "`threshold_v` (volts)",
            },
            LOOKS,
            "the same divider (LDR and 10 kOhm); a fixed light unless a scenario sets it",
            photoresistor,
        ),
        PartMap(
            "wokwi-hc-sr04",
            "hcsr04",
            {"distance": "a box that far (cm) in front of it on a `desk` body"},
            LOOKS,
            "no noise (noise_sd_m = 0); the echo is 58.31 us per cm; nothing nearer than 2 cm",
            hc_sr04,
        ),
        PartMap(
            "wokwi-servo",
            "servo",
            {},
            (*LOOKS, "horn", "hornColor"),
            "0 to 180 degrees for 500 to 2500 us pulses at 50 Hz (SG90); starts at 0 degrees; turns at 600 deg/s",
            servo,
        ),
        PartMap(
            "wokwi-relay-module",
            "relay",
            {"transistor": "`active_low` (pnp: true)"},
            LOOKS,
            "the contacts switch no circuit: `<id>_closed` in the truth",
            relay,
        ),
        PartMap("wokwi-neopixel", "ws2812_strip", {}, LOOKS, "one LED; a chain through DOUT is refused", neopixel),
        PartMap(
            "wokwi-led-ring",
            "ws2812_strip",
            {"pixels": "`count`"},
            (*LOOKS, "pixelSpacing", "background"),
            "WS2812 timing is checked (a stream out of tolerance is counted)",
            led_ring,
        ),
        PartMap(
            "wokwi-neopixel-matrix",
            "ws2812_strip",
            {"rows": "`count` = rows x cols", "cols": "`count`"},
            (*LOOKS, "pixelate", "layout", "brightness", "animation"),
            "one strip in the order the data runs; at most 256 LEDs",
            neopixel_matrix,
        ),
        PartMap(
            "wokwi-mpu6050",
            "mpu6050",
            {
                "accelX": "only 0 g (a still board)",
                "accelY": "only 0 g",
                "accelZ": "only 1 g",
                "rotationX": "`gyro_bias_dps` x (deg/s)",
                "rotationY": "`gyro_bias_dps` y",
                "rotationZ": "`gyro_bias_dps` z",
                "temperature": "only 25 (degrees C, what the chip reads)",
            },
            LOOKS,
            "reads the desk's motion (still); no noise; AD0 to a supply: 0x69; the bus as the code makes it",
            mpu6050,
        ),
        PartMap(
            "board-ssd1306",
            "ssd1306",
            {"i2cAddress": "`address` (0x3c or 0x3d)"},
            LOOKS,
            "128 x 64 on I2C; the picture is kept as PNG and GIF",
            ssd1306,
        ),
        PartMap(
            "wokwi-dht22",
            "dht",
            {"temperature": "`temperature_c` (-40 to 80)", "humidity": "`humidity_pct` (0 to 100)"},
            LOOKS,
            "the dht module's read is answered a frame at a time (the start pulse is on the pin; the 40 bits' "
            "timing is the clock's, not edges); a read sooner than 2 s after the last is fresh, not the last "
            "value; set-control `temperature`, `humidity`",
            dht,
        ),
        PartMap(
            "wokwi-dht11",
            "dht",
            {"temperature": "`temperature_c` (0 to 50)", "humidity": "`humidity_pct` (20 to 90)"},
            LOOKS,
            "whole degrees and percent; as wokwi-dht22",
            dht,
        ),
        PartMap(
            "wokwi-lcd1602",
            "char_lcd",
            {
                "pins": 'only "i2c" (the PCF8574 backpack); "full" (parallel) is refused',
                "i2cAddress": "`address` (0x27 by default)",
            },
            (*LOOKS, "background", "characters"),
            "16 x 2; HD44780 in 4-bit mode behind a PCF8574 (P0 RS, P1 RW, P2 E, P3 backlight, P4-P7 D4-D7); "
            "its text is kept, not drawn; no busy flag, no instruction times",
            lcd1602,
        ),
        PartMap(
            "wokwi-lcd2004",
            "char_lcd",
            {"pins": "as wokwi-lcd1602", "i2cAddress": "as wokwi-lcd1602"},
            (*LOOKS, "background", "characters"),
            "20 x 4, rows at DDRAM 0x00, 0x40, 0x14, 0x54; as wokwi-lcd1602",
            lcd2004,
        ),
        PartMap(
            "wokwi-buzzer",
            "buzzer",
            {"mode": "none: no sound here (checked: smooth or accurate)", "volume": "none (checked: 0.01 to 1)"},
            LOOKS,
            "its tones are recorded (frequency, start, end: `<id>_freq_hz`, `<id>_tones`); a PWM of duty 0 or full, "
            "or a plain level, is silence",
            buzzer,
        ),
        PartMap(
            "wokwi-ky-040",
            "rotary_knob",
            {},
            LOOKS,
            "turned by `turns` ([t_s, detents], negative: counter-clockwise), 4 edges 1 ms apart a detent, CLK "
            "leading clockwise; SW pressed by `presses` or set-control `pressed`; no bounce",
            ky040,
        ),
        PartMap(
            "wokwi-logic-analyzer",
            "(probe pins)",
            {},
            (*LOOKS, "bufferSize", "channels", "colors", "triggerMode", "triggerPin", "filename"),
            "no part: each channel D0..D7 is a `probe:<id>_D<n>` pin, in the trace and its VCD",
            logic_analyzer,
        ),
        PartMap(
            "wokwi-resistor",
            "(none)",
            {},
            (*LOOKS, "value"),
            "a wire for signals (a series resistor), not for rails (a pull-up is not a supply)",
            resistor,
        ),
    )
}
"""The Wokwi parts we map, by type."""

REFUSED = {
    "wokwi-ntc-temperature-sensor": "no thermistor part",
    "wokwi-ds1307": "no RTC chip part (the board's clock is the virtual one)",
    "wokwi-membrane-keypad": "no keypad part",
    "wokwi-7segment": "no 7-segment display part (its segments could be LEDs)",
    "wokwi-stepper-motor": "no stepper part",
    "wokwi-a4988": "no stepper driver part",
    "wokwi-ir-receiver": "no IR part",
    "wokwi-pir-motion-sensor": "no PIR part",
    "wokwi-analog-joystick": "no joystick part (two potentiometers and a button would do)",
    "wokwi-led-bar-graph": "no bar graph part (ten LEDs would do)",
    "wokwi-ili9341": "no TFT display part (SSD1306 only)",
    "wokwi-microsd-card": "no SD card part",
    "wokwi-hx711": "no load-cell amplifier part",
    "wokwi-max7219-matrix": "no MAX7219 part",
    "wokwi-dip-switch-8": "no DIP switch part (slide switches would do)",
}
"""Wokwi parts seen in public MicroPython projects that we do not map, and why."""


def mapper(part) -> PartMap:
    """The part's map; an unknown or refused type, or an unknown attribute, is one error
    naming it and the nearest we have."""
    if part.type not in TABLE:
        near = difflib.get_close_matches(part.type, list(TABLE), n=1, cutoff=0)
        why = f"not mapped ({REFUSED[part.type]})" if part.type in REFUSED else "unknown part"
        raise _error(part, f"{why}; nearest we have: {near[0]!r}")
    pmap = TABLE[part.type]
    known = [*pmap.attrs, *pmap.cosmetic]
    for name in part.attrs:
        if name not in known:
            near = difflib.get_close_matches(name, known, n=1, cutoff=0)
            hint = f"; nearest: {near[0]!r}" if near else " (it has none)"
            raise _error(part, f"attrs.{name}: unknown attribute{hint}")
    return pmap
