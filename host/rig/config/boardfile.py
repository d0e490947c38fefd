"""Rig files with several boards (``docs/multi-board.md``): one ``[plant]`` and a
``[[boards]]`` table for each board, with its name, firmware, board (name, file or pins,
family), wiring, budgets and interpreter settings. Each board is checked as a rig file of
its own over the one plant (:func:`host.rig.config.rigfile.rig_from_data`), so every mistake
names the file, the board and the field as a one-board rig file's would.

The wires between boards are parts of the plant: a ``board_uart`` (one board's UART wired
to ``<name>.a``, the other's to ``<name>.b``), a ``wire`` (one board's output pin to
``<name>.in``, the other's input to ``<name>.out``).
"""

import dataclasses
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from host.core.errors import ConfigError
from host.rig.config.app import App
from host.rig.config.rigfile import MAX_RIG_BYTES, _name, _Where, rig_from_data
from host.rig.config.tomlfile import read_toml

TOP_KEYS = {
    "name": str,
    "description": str,
    "plant": dict,
    "world": dict,
    "worlds": dict,
    "boards": list,
    "budgets": dict,
}
REACTION_KEYS = {"kind": str, "stimulus": str, "response": str, "limit_us": int, "description": str}
BOARD_KEYS = {
    "name": str,
    "description": str,
    "firmware": dict,
    "board": (dict, str),
    "wiring": dict,
    "budgets": dict,
    "interpreter": dict,
    "trace": dict,
}
MAX_BOARDS = 8


@dataclass(frozen=True)
class Boards:
    """A rig with several boards: each board's app by its name (in the file's order), and
    the one plant's builder."""

    name: str
    apps: dict  # board name -> its App, or a ProgramSpec (a host program)
    make_plant: Callable
    rig_file: Path | None = None
    i2c_links: dict = field(default_factory=dict)
    """(controller board, its bus) -> the target board: the plant's ``board_i2c`` parts."""
    budgets: dict = field(default_factory=dict)
    """Budgets across boards (the file's top-level ``[budgets.<name>]``): name -> (stimulus,
    response, limit_us, description), each end (board, signal)."""

    def firmware(self) -> dict:
        """The boards that run firmware (the others are host programs), by name."""
        return {name: app for name, app in self.apps.items() if isinstance(app, App)}


PROGRAM_KEYS = {"name": str, "description": str, "program": str}


@dataclass(frozen=True)
class ProgramSpec:
    """A ``[[boards]]`` table with ``program``: a host program standing in for a board
    (``host.rig.loop.hostboard``): its Python file and the function it calls with the board."""

    path: Path
    function: str = "main"


def is_multi_board(data: dict) -> bool:
    return isinstance(data, dict) and "boards" in data


def names_boards(name: str) -> bool:
    """``name`` is a rig file (or a folder's rig.toml) with ``[[boards]]``: a quick look, the
    file read and checked whole by :func:`load_boards`."""
    path = Path(name)
    try:
        path = path / "rig.toml" if path.is_dir() else path
        if path.suffix != ".toml" or not path.is_file():
            return False
    except (OSError, ValueError):  # (a name too long, a NUL: the one-board reader says so)
        return False
    try:
        return is_multi_board(read_toml(path, "rig file", MAX_RIG_BYTES))
    except ConfigError:
        return False  # (the one-board reader says what is wrong with it)


def load_boards(path) -> Boards:
    """Read and check a rig file with ``[[boards]]`` (or a folder's rig.toml); the boards it describes."""
    path = Path(path)
    path = path / "rig.toml" if path.is_dir() else path
    return boards_from_data(path, read_toml(path, "rig file", MAX_RIG_BYTES))


def boards_from_data(path, data: dict) -> Boards:
    path = Path(path)
    where = _Where(path)
    where.table(data, "top level:", TOP_KEYS, required=("plant", "boards"))
    entries = data["boards"]
    if not 1 <= len(entries) <= MAX_BOARDS or not all(isinstance(e, dict) for e in entries):
        raise where.error("[[boards]]", f"expected 1 to {MAX_BOARDS} tables, got {len(entries)} entries")
    name = _name(where, "name", data.get("name") or path.parent.name)
    apps: dict[str, App | ProgramSpec] = {}
    for number, entry in enumerate(entries, 1):
        field = f"[[boards]] #{number}"
        program = "program" in entry
        where.table(
            entry, field, PROGRAM_KEYS if program else BOARD_KEYS, required=("name",) if program else ("name", "wiring")
        )
        board = _name(where, f"{field} name", entry["name"])
        if board in apps:
            raise where.error(f"{field} name", f"a second board named {board!r}: expected one name per board")
        if program:
            apps[board] = _program(where, path, entry["program"], f"[[boards]] {board} program")
        else:
            apps[board] = _board_app(path, data, entry, f"{name}.{board}", f"[[boards]] {board}")
    firmware = [a for a in apps.values() if isinstance(a, App)]
    if not firmware:
        raise where.error("[[boards]]", "expected at least one board with firmware (the others may be host programs)")
    first = firmware[0]
    links = _i2c_links(where, data["plant"], apps)
    budgets = _reaction_budgets(where, data.get("budgets", {}), apps)
    return Boards(name=name, apps=apps, make_plant=first.make_plant, rig_file=path, i2c_links=links, budgets=budgets)


def _reaction_budgets(where, table: dict, apps: dict) -> dict:
    """The top-level ``[budgets.<name>]`` of a rig file with several boards: each a
    ``reaction`` from a signal one board drives to a signal another drives (``board:signal``,
    the signal one of that board's pins is wired to: a plant input or a probe)."""
    budgets = {}
    for name, entry in table.items():
        field = f"[budgets.{name}]"
        if not isinstance(entry, dict):
            raise where.error(field, f"expected a table, got {entry!r}")
        where.table(entry, field, REACTION_KEYS, required=("kind", "stimulus", "response", "limit_us"))
        if entry["kind"] != "reaction":
            raise where.error(
                f"{field} kind",
                f"expected 'reaction' (a budget across boards; one board's own budgets go in its [[boards]] "
                f"table), got {entry['kind']!r}",
            )
        ends = []
        for role in ("stimulus", "response"):
            board, _, signal = entry[role].partition(":")
            app = apps.get(board)
            if not isinstance(app, App):
                boards = ", ".join(b for b, a in apps.items() if isinstance(a, App))
                raise where.error(
                    f"{field} {role}",
                    f"expected '<board>:<signal>' of a board with firmware ({boards}), got {entry[role]!r}",
                )
            if signal not in app.wiring.values():
                wired = ", ".join(sorted(app.wiring.values()))
                raise where.error(f"{field} {role}", f"board {board} wires no pin to {signal!r} (its signals: {wired})")
            ends.append((board, signal))
        if not 0 < entry["limit_us"] <= 3_600_000_000:
            raise where.error(f"{field} limit_us", f"expected a time in us from 1 to an hour, got {entry['limit_us']}")
        budgets[name] = (ends[0], ends[1], entry["limit_us"], entry.get("description", ""))
    return budgets


def _i2c_links(where, plant: dict, apps: dict) -> dict:
    """The ``board_i2c`` parts (their options checked by the plant's builder): (controller,
    bus) -> target, each naming boards of the file."""
    links: dict = {}
    parts = plant.get("parts", []) if isinstance(plant, dict) else []
    for number, part in enumerate(parts, 1):
        if not isinstance(part, dict) or part.get("kind") != "board_i2c":
            continue
        label = f"[[plant.parts]] {part.get('name') or f'#{number}'}"
        for role in ("controller", "target"):
            if part.get(role) not in apps:
                raise where.error(
                    f"{label} {role}", f"expected one of the boards {', '.join(apps)}, got {part.get(role)!r}"
                )
        key = (part["controller"], part.get("controller_bus", "i2c0"))
        if key in links:
            raise where.error(
                f"{label} bus", f"a second board_i2c on board {key[0]}'s {key[1]}: expected one target board a bus"
            )
        links[key] = part["target"]
    return links


def _program(where, path: Path, given: str, field: str) -> ProgramSpec:
    """``program = "master.py"`` or ``"master.py:run"``: a Python file beside the rig file
    (relative to its folder) and the function it calls (``main`` by default)."""
    file, _, function = given.partition(":")
    function = function or "main"
    if not file.endswith(".py") or not function.isidentifier():
        raise where.error(
            field, f"expected a Python file and maybe its function (master.py, master.py:run), got {given!r}"
        )
    found = (path.parent / file).resolve()
    if not found.is_file():
        raise where.error(field, f"no such file {found}")
    return ProgramSpec(found, function)


def _board_app(path: Path, data: dict, entry: dict, app_name: str, field: str) -> App:
    """One board as the one-board rig file it amounts to: its tables over the shared plant."""
    one = {k: v for k, v in entry.items() if k not in ("name",)}
    one["name"] = app_name
    one["plant"] = data["plant"]
    for shared in ("world", "worlds"):  # (the plant's, so every board's: BoardSet(world=) picks one)
        if shared in data:
            one[shared] = data[shared]
    one.setdefault("firmware", {})
    try:
        app = rig_from_data(path, one)
    except ConfigError as e:
        text = str(e)
        prefix = f"{path}: "
        raise ConfigError(f"{prefix}{field}: {text.removeprefix(prefix)}") from None
    return dataclasses.replace(app, board=dataclasses.replace(app.board, in_set=entry["name"]))


def apps_of(path) -> list[App]:
    """The apps of any rig file: its one board's, or each of its ``[[boards]]``'s."""
    path = Path(path)
    data = read_toml(path, "rig file", MAX_RIG_BYTES)
    if is_multi_board(data):
        return [a for a in boards_from_data(path, data).apps.values() if isinstance(a, App)]
    return [rig_from_data(path, data)]
