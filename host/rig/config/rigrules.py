"""The rules a rig file's fields must keep together, which no one field shows wrong alone:
what a board could not be wired as, and what a run could not mean.

- **One line, one use.** A pin is wired once; a plant input is driven by one pin (or by
  one device: a PWM expander's channel); a probe watches one pin; a pin a bus runs on
  (a SoftI2C's ``i2c:<scl>,<sda>``, a SoftSPI's ``spi:<sck>,<mosi>,<miso>``, a DHT's
  ``dht:<pin>``, ``onewire:<pin>``) is no other bus's and no wired pin, and appears once in its bus.
- **Only what the board has.** A pin number in a bus's name is one of the family's GPIOs;
  a board's bus controller (``i2c<n>``, ``spi<n>``) is one the family has (as the shim's
  ``machine.I2C``/``SPI`` take them: ``host/shim/_hilbus.py``, after MicroPython's
  ``ports/esp32/machine_i2c.c``, ``machine_hw_spi.c``, ``ports/rp2/machine_i2c.c``,
  ``machine_spi.c``).
- **A start that can happen.** The body's start pose (each world's) is in free floor:
  inside the room, outside every obstacle, the body clear of every wall (touching at most).

Each rule raises the rig file's :class:`~host.core.errors.ConfigError`, naming the field
and both sides of the clash, through ``where.error(field, message)``.
"""

import math
import re

from host.rig.config.app import PROBE_PREFIX
from host.rig.scan.boards import pin_key
from sim_plant.names import unknown
from sim_plant.option_table import SAFE_NAME

PIN_RANGES = {"esp32": 48, "rp2": 47}
"""The highest GPIO of each family, by ``sys.platform`` (ESP32-S3: 48, RP2350B: 47)."""
MAX_PIN = 255  # a board of no known family
BUS_IDS = {"rp2": {"i2c": (0, 1), "spi": (0, 1)}}
"""A family's bus controllers by ``sys.platform``; any other (an ESP32, the unix port's
boards of no family): I2C 0 and 1, SPI 1 and 2 (HSPI and VSPI)."""
OTHER_BUS_IDS = {"i2c": (0, 1), "spi": (1, 2)}
HARDWARE_BUS = re.compile(r"(i2c|spi)([0-9])")
GPIO_NAME = re.compile(r"(?:GP|GPIO|D)?([0-9]+)")  # 16, GP16, GPIO16: a number of the family's
OVERLAP_M = 0.001  # a body may start touching a wall, not inside it


def highest_pin(platform: str | None) -> int:
    return PIN_RANGES.get(platform or "", MAX_PIN)


def plain_name(name) -> str | None:
    """Why ``name`` cannot be a part's or a probe's name (None: it can): one path component
    of letters, digits, ``_ + -`` (no ``.``: a signal is ``<name>.<signal>``)."""
    if isinstance(name, str) and SAFE_NAME.fullmatch(name) and "." not in name:
        return None
    shown = repr(name) if len(repr(name)) < 70 else repr(name)[:66] + "..."
    return f"expected a name of letters, digits, '_', '+' or '-' (no '.', no '/', at most 64), got {shown}"


def check_wiring(where, wiring: dict, pins: dict, plant, platform: str | None = None) -> None:
    """Each wired pin one the family has; one pin for each plant input and each probe;
    probes named as one path component."""
    highest = highest_pin(platform)
    for name in wiring:
        number = _gpio(str(pins.get(name, "")))
        if not name.endswith("_UART") and number is not None and number > highest:
            raise where.error(
                f"[wiring] {name}",
                f"pin {name} = {pins[name]!r}: expected a GPIO from 0 to {highest} ({_family(platform)}'s)",
            )
    inputs = set(plant.inputs)
    driven = plant.driven_inputs()
    by_signal: dict = {}
    for pin, signal in wiring.items():
        field = f"[wiring] {pin}"
        if signal.startswith(PROBE_PREFIX):
            problem = plain_name(signal[len(PROBE_PREFIX) :])
            if problem:
                raise where.error(field, f"a probe's name: {problem}")
        if signal in driven:
            raise where.error(
                field, f"{signal} is driven by a device of the plant (a PWM expander's channel): no pin may drive it"
            )
        if signal in inputs or signal.startswith(PROBE_PREFIX):
            other = by_signal.setdefault(signal, pin)
            if other != pin:
                what = "one probe watches one pin" if signal.startswith(PROBE_PREFIX) else "two outputs on one line"
                raise where.error(field, f"{signal} is wired to {other} too ({what}): expected one pin for it")


def check_boards(where, also: tuple, wiring: dict, known: list, read_pins) -> None:
    """Each ``[board] also`` is a board of ours that has every wired pin's name."""
    for name in also:
        if name not in known:
            raise where.error("[board] also", f"no board {name!r} {unknown(name, known, what='boards')}")
        missing = [pin for pin in wiring if pin not in read_pins(name)]
        if missing:
            raise where.error(
                "[board] also", f"board {name} has no pin named {', '.join(missing)} (the wiring needs every one)"
            )


def bus_pins(bus: str) -> list[str]:
    """The pins a bus's name gives (a SoftI2C's, a SoftSPI's, a DHT's line), as the shim names them."""
    if ":" not in bus:
        return []
    return [p for p in bus.split(":", 1)[1].split(",") if p]


def check_buses(where, plant, wiring: dict, pins: dict, platform: str | None) -> None:
    """Every bus a part is on: a controller the family has, pins the family has, each pin
    once and on no other bus and wired to nothing."""
    wired = {_line(pin_key(name, pins[name])): name for name in wiring if name in pins}
    taken: dict = {}  # pin -> (bus, the field that put it there)
    highest = highest_pin(platform)
    for field, bus in _bus_fields(plant):
        shown = _short(bus)
        hard = HARDWARE_BUS.fullmatch(bus)
        if hard:
            ids = BUS_IDS.get(platform or "", OTHER_BUS_IDS)[hard.group(1)]
            if int(hard.group(2)) not in ids:
                has = [f"{hard.group(1)}{i}" for i in ids]
                soft = "i2c:<scl>,<sda>" if hard.group(1) == "i2c" else "spi:<sck>,<mosi>,<miso>"
                raise where.error(
                    field,
                    f"{_family(platform)} has no bus {shown} {unknown(bus, has, what='its ' + hard.group(1).upper())}"
                    f"; or {soft} for a software bus on any pins",
                )
            continue
        seen: list = []
        for pin in bus_pins(bus):
            number = _gpio(pin)
            if number is not None and number > highest:
                expected = f"expected a GPIO from 0 to {highest} ({_family(platform)}'s)"
                raise where.error(field, f"pin {_short(pin)} of bus {shown}: {expected}")
            if _line(pin) in seen:
                raise where.error(field, f"pin {_short(pin)} is twice in bus {shown}: expected a pin for each line")
            seen.append(_line(pin))
            if _line(pin) in wired:
                name = wired[_line(pin)]
                raise where.error(
                    field,
                    f"pin {_short(pin)} of bus {shown} is wired as {name} = {pins[name]} to {wiring[name]} too: "
                    "one pin is one line (move the bus or the wire)",
                )
            other = taken.setdefault(_line(pin), (bus, field))
            if other[0] != bus:
                clash = f"pin {_short(pin)} of bus {shown} is bus {_short(other[0])}'s too ({other[1]})"
                raise where.error(field, f"{clash}: one pin is one line")


def _short(text: str) -> str:
    return text if len(text) <= 40 else text[:37] + "..."


def _gpio(pin: str) -> int | None:
    """The GPIO a pin's name is (``GP5``, ``GPIO5``, ``D5``, ``5``: 5), None for a name;
    a number of more digits than any GPIO has: past every family's (not read whole)."""
    number = GPIO_NAME.fullmatch(pin)
    if number is None:
        return None
    digits = number.group(1)
    return int(digits) if len(digits) <= 6 else MAX_PIN + 1


def _line(pin: str) -> str:
    """A pin as the line it is: ``GP5``, ``GPIO5``, ``D5`` and ``5`` are GPIO 5."""
    number = _gpio(pin)
    return pin if number is None or number > MAX_PIN else str(number)


def _family(platform: str | None) -> str:
    return f"the {platform} family" if platform else "a board of no family ([board] family)"


def _bus_fields(plant):
    """(the field that names it, bus) for each part on a bus (each device, for a plant of a kind)."""
    parts = plant.catalogue_parts
    if parts:
        return [(f"{p.label} bus", p.options["bus"]) for p in parts if p.on_bus and p.options.get("bus")]
    return [(f"[plant] ({d.label}) bus", d.bus) for d in plant.bus_devices()]


def check_start(where, field: str, plant) -> None:
    """The body starts in free floor: each of its circles' centres inside the room and
    outside every obstacle of the world, and no circle into a wall by more than
    ``OVERLAP_M`` (a plant with no world or no body: nothing to check)."""
    world, circles = plant.world, plant.footprint()
    start = plant.start_pose  # (as given: the plant pushes a body out of a wall at reset)
    if world is None or not world.walls or not circles or start is None:
        return
    x, y, theta = (float(v) for v in start)
    c, s = math.cos(theta), math.sin(theta)
    for ox, oy, r in circles:
        px, py = x + ox * c - oy * s, y + ox * s + oy * c
        if not world.contains(px, py):
            raise where.error(
                field,
                f"the start pose ({x:g}, {y:g}) puts the body at ({px:g}, {py:g}), inside an obstacle or outside "
                "the room: expected a start pose in free floor",
            )
        gap, _nx, _ny = world.clearance(px, py)
        if gap - r < -OVERLAP_M:
            raise where.error(
                field,
                f"the start pose ({x:g}, {y:g}) puts the body {(r - gap) * 1000:.0f} mm into a wall or an obstacle "
                f"(its circle of {r:g} m at ({px:g}, {py:g})): expected a start pose where the body fits",
            )
