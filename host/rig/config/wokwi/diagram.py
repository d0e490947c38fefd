"""A ``diagram.json`` read and checked: its parts (type, id, attributes), its board, and
its connections as nets.

Wokwi's ``connections`` are ``[from, to, colour, route]`` with ends ``"partId:pin"``;
the colour and the route only draw the wire. A net is every pin a wire joins, and the
pins a part joins inside itself (a push-button's ``1.l`` and ``1.r``). A resistor joins
its ends for signals (a series resistor before an LED) but not for rails: a pin pulled
up through one is not tied to the supply. ``$serialMonitor`` is the console, which the
rig has anyway."""

import difflib
import re
from dataclasses import dataclass, field
from pathlib import Path

from host.core.errors import ConfigError
from host.core.nesting import loads_json
from host.rig.config.wokwi.boards import BOARDS, Board, rail

MAX_DIAGRAM_BYTES = 1 << 20
JOINED_INSIDE = {  # part type -> groups of its pins that are one conductor
    "wokwi-pushbutton": (("1.l", "1.r"), ("2.l", "2.r")),
    "wokwi-pushbutton-6mm": (("1.l", "1.r"), ("2.l", "2.r")),
}
PASSIVE = {"wokwi-resistor": ("1", "2")}  # joined for signals, not for rails
CONSOLE = "$serialMonitor"


@dataclass
class Part:
    """One entry of ``parts``: its place in the list (for messages), type, id, attributes."""

    index: int
    type: str
    id: str
    attrs: dict

    def where(self) -> str:
        return f"parts[{self.index}] ({self.id!r}, {self.type})"


@dataclass
class Diagram:
    """The parts, the board (its part and its :class:`Board`), and the nets."""

    path: Path
    parts: list
    board_part: Part
    board: Board
    wires: list = field(default_factory=list)  # (a, b) "id:pin" pairs, console wires left out

    def error(self, message: str) -> ConfigError:
        return ConfigError(f"{self.path}: {message}")

    def __post_init__(self):
        self.strong = _Nets()  # wires and a part's own joins
        self.signal = _Nets()  # and through resistors
        by_id = {p.id: p for p in self.parts}
        for a, b in self.wires:
            self.strong.join(a, b)
            self.signal.join(a, b)
        for part in self.parts:
            for group in JOINED_INSIDE.get(part.type, ()):
                for pin in group[1:]:
                    self.strong.join(f"{part.id}:{group[0]}", f"{part.id}:{pin}")
                    self.signal.join(f"{part.id}:{group[0]}", f"{part.id}:{pin}")
            if part.type in PASSIVE:
                one, two = PASSIVE[part.type]
                self.signal.join(f"{part.id}:{one}", f"{part.id}:{two}")
        self.by_id = by_id

    def board_pins(self, end: str, through_resistors: bool = True) -> list[str]:
        """The board's pins on ``end``'s net (``"led1:A"`` -> ``["D13"]``)."""
        nets = self.signal if through_resistors else self.strong
        prefix = f"{self.board_part.id}:"
        return sorted(n[len(prefix) :] for n in nets.members(end) if n.startswith(prefix))

    def gpio(self, end: str) -> tuple[str, int] | None:
        """(the pin's key in the rig, its GPIO) of the one GPIO on ``end``'s net, None for none;
        two GPIOs on one net are refused."""
        pins = [(p, self.board.gpio(p)) for p in self.board_pins(end)]
        gpios = [(self.board.key(p), n) for p, n in pins if n is not None]
        if len(gpios) > 1:
            names = ", ".join(k for k, _ in gpios)
            raise self.error(f"connections: {end} is wired to {names}: two board pins on one net")
        return gpios[0] if gpios else None

    def rail(self, end: str) -> object:
        """GND, 3.3 or 5.0 when ``end`` is wired (not through a resistor) to the board's
        ground or a supply pin, else None; ground and a supply on one net are refused."""
        rails = sorted({rail(p) for p in self.board_pins(end, through_resistors=False)} - {None}, key=str)
        if len(rails) > 1:
            raise self.error(f"connections: {end} is wired to {' and '.join(map(str, rails))}: a short")
        return rails[0] if rails else None


class _Nets:
    """Union-find over ``"id:pin"`` names."""

    def __init__(self):
        self.parent: dict[str, str] = {}

    def find(self, a: str) -> str:
        self.parent.setdefault(a, a)
        while self.parent[a] != a:
            self.parent[a] = self.parent[self.parent[a]]
            a = self.parent[a]
        return a

    def join(self, a: str, b: str) -> None:
        self.parent[self.find(a)] = self.find(b)

    def members(self, a: str) -> list[str]:
        root = self.find(a)
        return [n for n in list(self.parent) if self.find(n) == root]


def read_diagram(path: Path) -> Diagram:
    """The diagram at ``path``, checked: JSON of parts and connections, one board we run."""
    try:
        raw = path.read_bytes()
    except OSError as e:
        raise ConfigError(f"{path}: cannot read: {e.strerror or e}") from None
    if len(raw) > MAX_DIAGRAM_BYTES:
        raise ConfigError(f"{path}: {len(raw)} bytes: expected a diagram of at most {MAX_DIAGRAM_BYTES}")
    data = loads_json(raw, str(path))
    if not isinstance(data, dict) or not isinstance(data.get("parts"), list):
        raise ConfigError(f"{path}: expected an object with a list of parts (Wokwi's diagram format)")
    parts = [_part(path, i, p) for i, p in enumerate(data["parts"])]
    ids = [p.id for p in parts]
    twice = sorted({i for i in ids if ids.count(i) > 1})
    if twice:
        raise ConfigError(f"{path}: parts: the id {twice[0]!r} is given twice: each part needs its own")
    boards = [p for p in parts if p.type in BOARDS]
    if not boards:  # a board of Wokwi's we do not run (an Arduino, an STM32), or a misspelt one
        others = [p for p in parts if p.type.startswith("board-") or difflib.get_close_matches(p.type, list(BOARDS))]
        other = next((p for p in others if p.type != "board-ssd1306"), None)
        if other is None:
            raise ConfigError(f"{path}: expected one board part ({', '.join(BOARDS)}), got none")
        near = difflib.get_close_matches(other.type, list(BOARDS), n=1, cutoff=0)
        raise ConfigError(f"{path}: {other.where()}: a board we do not run; nearest we have: {near[0]!r}")
    if len(boards) > 1:
        found = ", ".join(f"{p.id} ({p.type})" for p in boards)
        raise ConfigError(f"{path}: expected one board part, got {found}: one board a rig")
    board_part = boards[0]
    wires = _wires(path, data.get("connections", []), set(ids), board_part.id, BOARDS[board_part.type])
    return Diagram(path, [p for p in parts if p is not board_part], board_part, BOARDS[board_part.type], wires)


def _board_pin(path: Path, i: int, end: str, board) -> None:
    """A board pin a wire ends on is one the board has: a GPIO numbered past its highest
    (``esp:99``, ``pico:GP40``) is refused with the board's GPIO names."""
    style = {"devkit_v1": r"D\d+", "number": r"\d+", "pico": r"GP\d+"}[board.style]
    pin = end.partition(":")[2]
    if not re.fullmatch(rf"{style}|GPIO\d+|\d+", pin) or board.gpio(pin) is not None:
        return
    example = {"devkit_v1": "D{}", "number": "{}", "pico": "GP{}"}[board.style]
    names = [example.format(n) for n in range(board.highest + 1)] + [n for n, _ in board.named]
    close = difflib.get_close_matches(pin, names, n=3)
    near = f"; nearest: {', '.join(close)}" if close else ""
    also = "".join(f", {n}" for n in names[board.highest + 1 :])
    raise ConfigError(
        f"{path}: connections[{i}]: {end[:60]}: the {board.title} has no pin {pin[:40]!r} (its GPIOs: "
        f"{example.format(0)} to {example.format(board.highest)}{also}; and its ground and supply pins){near}"
    )


def _part(path: Path, i: int, entry) -> Part:
    if not isinstance(entry, dict) or not isinstance(entry.get("type"), str) or not isinstance(entry.get("id"), str):
        raise ConfigError(f"{path}: parts[{i}]: expected an object with a type and an id, got {str(entry)[:80]}")
    attrs = entry.get("attrs", {})
    if not isinstance(attrs, dict):
        raise ConfigError(f"{path}: parts[{i}] ({entry['id']!r}) attrs: expected an object, got {attrs!r}"[:200])
    return Part(i, entry["type"], entry["id"], {str(k): v for k, v in attrs.items()})


def _wires(path: Path, connections, ids: set, board_id: str, board) -> list[tuple[str, str]]:
    if not isinstance(connections, list):
        raise ConfigError(f"{path}: connections: expected a list, got {str(connections)[:80]}")
    wires = []
    for i, c in enumerate(connections):
        ok = isinstance(c, list) and len(c) >= 2 and all(isinstance(e, str) and ":" in e for e in c[:2])
        if not ok:
            raise ConfigError(
                f'{path}: connections[{i}]: expected ["part:pin", "part:pin", colour, route], got {c!r}'[:200]
            )
        a, b = c[0], c[1]
        if CONSOLE in (a.split(":")[0], b.split(":")[0]):
            continue  # the console: the rig's REPL UART
        for end in (a, b):
            part_id = end.split(":", 1)[0]
            if part_id not in ids:
                hint = difflib.get_close_matches(part_id, list(ids), n=1)
                near = f"; nearest: {hint[0]!r}" if hint else ""
                raise ConfigError(f"{path}: connections[{i}]: {end}: no part with id {part_id!r}{near}")
            if part_id == board_id:
                _board_pin(path, i, end, board)
        wires.append((a, b))
    return wires
