"""Part ``external``: a device served by a program outside the rig, in any language
(``docs/external.md``): a chip on I2C at an address, pins the firmware drives and reads, a
UART's line, or any of these at once, one program serving them all. The rig starts
``command`` (a file relative to the rig file, run as it is: its ``#!`` line says what runs
it) when it first needs it and writes one JSON line a request on its standard input, each
stamped with its virtual instant (``t_us``), and reads the program's one-line answer before
it goes on: in lockstep, whatever the program's own speed.

    {"t_us": 0, "op": "reset", "levels": {"trig": 0}, ...}  ->  {"pins": [[50000, "button", 0]]}
    {"t_us": 1500, "op": "start", "read": false}             ->  {}
    {"t_us": 1500, "op": "write", "byte": 15}                ->  {"ack": true}
    {"t_us": 1500, "op": "read"}                             ->  {"byte": 104}
    {"t_us": 1500, "op": "stop"}                             ->  {}
    {"t_us": 2000, "op": "pins", "levels": {"trig": 1}}      ->  {"pins": [[3000, "echo", 1]]}
    {"t_us": 2000, "op": "uart", "baud": 9600, "bytes": [[3042, 112]]}  ->  {"uart": [[3542, "ok"]]}
    {"t_us": 9000, "op": "more"}                             ->  {"pins": [...], "until_us": 19000}

Any answer may carry a plan (``pins``, ``uart``, ``until_us``): the pins and the UART are
played from it on the plant's timeline (:mod:`sim_plant.physics.external`). The program
ends when its standard input closes (the rig stops: ``Plant.close``)."""

import itertools
import re
import weakref

from sim_plant.buses import BusDevice, BusName, check_placement
from sim_plant.catalogue.base import Build, Opt, PartType, Sig
from sim_plant.option_table import FileName, Flag, Num, OneOf, Row, Rows
from sim_plant.physics.external import _SERVERS, ExternalError, ExternalLines, Program, close

__all__ = ["External", "ExternalChip", "ExternalError"]

_KEYS = itertools.count(1)
PIN_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]{0,31}")
MAX_PINS = 32


class PinName:
    """A pin of an external part: a letter or ``_``, then letters, digits, ``_`` (at most
    32; not ``uart``, the UART's signal)."""

    what = "a pin's name (a letter or '_', then letters, digits or '_'; not 'uart')"

    def problem(self, value):
        if isinstance(value, str) and PIN_NAME.fullmatch(value) and value != "uart":
            return None
        return f"expected {self.what}, got {value!r}"[:200]


PIN_LEVEL = Row((PinName(), OneOf((0, 1))), "[pin, its level at reset (0 or 1)]")


class ExternalChip(BusDevice):
    """The part's chip on I2C: every byte of a transfer asked of the program; a plan in an
    answer goes to the part's pins and UART (``lines``)."""

    FIXED_STATE = (*BusDevice.FIXED_STATE, "key", "lines")

    def __init__(self, name: str, bus: str, address: int, key: int, lines: ExternalLines | None):
        super().__init__(name, bus, address)
        self.key, self.lines = key, lines

    def _ask(self, request: dict) -> dict:
        lines = self.lines
        if lines is not None:
            lines.begin()
        answer = _SERVERS[self.key].ask(request)
        if lines is not None:
            lines.take(request, answer)
        elif "pins" in answer or "uart" in answer:
            raise _SERVERS[self.key].error("expected no pins or uart (the part has none: pins_out, uart)", request)
        return answer

    def close(self) -> None:
        """The program's input closes and it ends (it starts again if asked again)."""
        program = _SERVERS.get(self.key)
        if program is not None:
            program.close()

    def begin(self, t_us, reading):
        self._ask({"t_us": t_us, "op": "start", "read": reading})

    def write(self, t_us, byte):
        return bool(self._ask({"t_us": t_us, "op": "write", "byte": byte}).get("ack", True))

    def read(self, t_us):
        request = {"t_us": t_us, "op": "read"}
        byte = self._ask(request).get("byte")
        if not isinstance(byte, int) or isinstance(byte, bool) or not 0 <= byte <= 0xFF:
            raise _SERVERS[self.key].error(f"expected {{'byte': 0..255}} for a read, got byte {byte!r}", request)
        return byte

    def end(self, t_us):
        self._ask({"t_us": t_us, "op": "stop"})


class External(PartType):
    CHIP = None  # (no register file of ours: the program's)
    kind = "external"
    MODELLED_FEATURES = (
        "every byte of every I2C transfer to its address, answered by its program in lockstep (docs/external.md)",
        "pins: the board outputs wired to it told at each change, its own pins' edges at the instants it plans",
        "a UART: the firmware's bytes stamped with their instants, the program's bytes at the instants it asks "
        "(10 bits a byte at baud)",
    )
    NOT_MODELLED = (
        "SPI",
        "clock stretching: the program's time is not the bus's",
        "an analog level (ADC) or a PWM's waveform: a pin is a level",
    )
    doc = (
        "A device served by a program outside the rig (any language: JSON lines on its stdin and stdout, "
        "stamped with virtual time): a chip on I2C, pins, a UART's bytes."
    )
    OPTIONS = (
        Opt("command", FileName(), None, "the program serving the device, relative to the rig file (run as it is)"),
        Opt("bus", BusName(), "i2c0", "the I2C bus its chip is on, as the firmware creates it"),
        Opt("address", Num("", 0, 127, whole=True, none=True), None, "its chip's 7-bit I2C address (unset: no chip)"),
        Opt("pins_in", Rows(PinName(), MAX_PINS), [], "the board outputs wired to it: signals <name>.<pin>"),
        Opt(
            "pins_out", Rows(PIN_LEVEL, MAX_PINS), [], "the pins it drives, [pin, level at reset]: signals <name>.<pin>"
        ),
        Opt("uart", Flag(), False, "a UART line, <name>.uart: the firmware's TX to it, its bytes to the RX"),
        Opt("baud", Num("bits per second", 300, 10_000_000, whole=True), 9600, "the speed of the bytes it sends"),
        Opt("timeout_s", Num("wall seconds", 0.1, 60), 5.0, "how long an answer may take before the run stops"),
    )
    SIGNALS = (
        Sig("<pin>", "in", "level", "each of pins_in: a board output; the program is told each change"),
        Sig("<pin>", "out", "level", "each of pins_out: a level the program drives, at the instants it plans"),
        Sig(
            "uart",
            "in",
            "uart",
            "the bytes a UART sends, to the program; (out, bytes) the bytes the program sends",
            (("uart", (True,)),),
        ),
    )
    TRUTH = ()

    def check(self) -> None:
        o = self.options
        self.on_bus = o["address"] is not None
        if self.on_bus:
            check_placement(o, "an external chip")
        pins = [*o["pins_in"], *(pin for pin, _ in o["pins_out"])]
        twice = next((pin for pin in pins if pins.count(pin) > 1), None)
        if twice is not None:
            raise ValueError(f"pins_in: expected each pin once, in pins_in or pins_out, got {twice!r} twice")

    def signals(self) -> dict[str, tuple[str, str]]:
        o = self.options
        signals = {f"{self.name}.{pin}": ("in", "level") for pin in o["pins_in"]}
        signals |= {f"{self.name}.{pin}": ("out", "level") for pin, _ in o["pins_out"]}
        if o["uart"]:
            signals[f"{self.name}.uart"] = ("in", "uart")
        return signals

    def add(self, build: Build) -> None:
        o = self.options
        serves_lines = bool(o["pins_in"] or o["pins_out"] or o["uart"])
        if not (serves_lines or self.on_bus):
            return  # (it serves nothing: its program is never started)
        key = next(_KEYS)
        where = f"{self.rig_file}: " if self.rig_file else ""
        reset = {"t_us": 0, "op": "reset", "levels": dict.fromkeys(o["pins_in"], 0), "outputs": dict(o["pins_out"])}
        if o["uart"]:
            reset["baud"] = o["baud"]
        if self.on_bus:
            reset["i2c"] = {"bus": o["bus"], "address": o["address"]}
        label = f"{where}{getattr(self, 'label', self.name)}"
        _SERVERS[key] = Program(label, o["command"], o["timeout_s"], reset)
        lines = (
            ExternalLines(self.name, key, o["pins_in"], dict(o["pins_out"]), o["uart"], o["baud"])
            if serves_lines
            else None
        )
        chip = ExternalChip(self.name, o["bus"], o["address"], key, lines) if self.on_bus else None
        build.parts.extend(p for p in (lines, chip) if p is not None)
        weakref.finalize(lines or chip, close, key)  # (the program ends with the plant, or at exit)
