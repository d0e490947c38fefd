"""Rig files: a firmware folder's test rig as data (TOML, ``docs/rig-file.md``).

A rig file names the firmware (folder, entry file, library folders), the board (a board
file or a pins table), the plant (a body and parts from :mod:`sim_plant.catalogue`), the
wiring (board pin -> plant signal), the timing budgets, the named worlds and interpreter
settings. It is checked whole before anything starts: every mistake raises a
:class:`~host.core.errors.ConfigError` that names the file and the field. Our own apps
are rig files too (``firmware/apps/<app>/rig*.toml``).
"""

import difflib
import re
from pathlib import Path

from host.core.errors import ConfigError, SetupError
from host.core.paths import BOARDS_DIR
from host.rig.config import budgets as budgets_of
from host.rig.config import migrate, rigrules
from host.rig.config.app import (
    CONSOLE_BAUD,
    ENTRY,
    PROBE_PREFIX,
    App,
    BoardSettings,
    Code,
    InterpreterSettings,
    Judge,
    PoseLine,
    Report,
    RunSettings,
)
from host.rig.config.tomlfile import NESTED_DEPTH, read_toml
from host.rig.scan.boards import (
    IDENTITIES,
    identity,
    known_boards,
    read_board_file,
    read_pin_map,
    with_builtin_lines,
)
from host.rig.targets import mcutime
from host.rig.targets.boardfs import confinement
from host.rig.targets.firmware import heap_bytes
from host.rig.targets.heap import HEAP_MAX_BYTES, HEAP_MIN_BYTES
from sim_plant import catalogue, option_table
from sim_plant.catalogue.assembly import PartsError, assemble, with_world
from sim_plant.faults import FaultError, parse_faults, with_faults
from sim_plant.names import unknown
from sim_plant.plant import check_contract

TABLES = {
    "name": str,
    "description": str,
    "firmware": dict,
    "board": dict,
    "plant": dict,
    "world": dict,
    "wiring": dict,
    "budgets": dict,
    "worlds": dict,
    "interpreter": dict,
    "faults": list,
    "report": dict,
    "trace": dict,
    "tests": dict,
}
TESTS_KEYS = {"exclude": list}  # (read by the pytest plugin: host/pytest_plugin/userpath.py)
REPORT_KEYS = {"views": list, "pose_line": dict, "judge": dict}
JUDGE_KEYS = {"console": str, "no_contact": bool, "home_within_m": (int, float), "min_coverage": (int, float)}
POSE_LINE_KEYS = {"tag": str, "columns": list, "m_per_unit": (int, float), "rad_per_unit": (int, float)}
POSE_LINE_KEYS |= {"probe": str, "what": str}
FIRMWARE_KEYS = {"dir": str, "entry": str, "lib": list, "harness_lib": bool, "allow_exit": bool}
BOARD_KEYS = {
    "name": str,
    "file": str,
    "pins": dict,
    "also": list,
    "family": str,
    "console_baud": int,
    "cpu": str,
}
BOARD_KEYS |= {"flash_size": (str, int), "allow_modules": dict, "sandbox": str}  # (host/rig/targets/boardfs.py)
INTERPRETER_KEYS = {"heap_size": (str, int), "ticks_wrap_s": (int, float), "version": str}
TYPE_NAMES = {str: "text", int: "an integer", float: "a number", bool: "true/false", list: "a list", dict: "a table"}
MAX_RIG_BYTES = 1 << 20  # a rig file is a page or two of TOML
MAX_DEPTH = NESTED_DEPTH  # tables and lists within each other (an obstacle in a world: 5)
CONTROL = re.compile(r"[\x00-\x08\x0a-\x1f\x7f-\x9f]")  # control characters (a tab is text)


class _Where:
    """A rig file and the field being read, for messages: ``rig.toml: [plant] kind: ...``."""

    def __init__(self, path: Path):
        self.path = path

    def error(self, field: str, message: str) -> ConfigError:
        return ConfigError(f"{self.path}: {field}: {message}")

    def table(self, data: dict, name: str, keys: dict, required=()) -> dict:
        """``data`` checked against ``keys`` (name -> type): unknown keys (with the
        closest known one), wrong types and missing required keys are errors."""
        for key, value in data.items():
            if key not in keys:
                hint = _did_you_mean(key, keys)
                raise self.error(f"{name} {key}".strip(), f"unknown key (known: {', '.join(keys)}){hint}")
            _check_type(self, f"{name} {key}", value, keys[key])
        missing = [k for k in required if k not in data]
        if missing:
            raise self.error(name.rstrip(":"), f"missing {', '.join(missing)}")
        return data


class _Within:
    """A world's field before the rule's own: ``[worlds.dark] [[plant.parts]] #3 (imu) bus``."""

    def __init__(self, where: _Where, prefix: str):
        self.where, self.prefix = where, prefix

    def error(self, field: str, message: str) -> ConfigError:
        return self.where.error(f"{self.prefix} {field}", message)


def _did_you_mean(word: str, choices) -> str:
    close = difflib.get_close_matches(word, list(choices), n=1)
    return f"; did you mean {close[0]!r}?" if close else ""


def _check_type(where: _Where, field: str, value, expected) -> None:
    types = expected if isinstance(expected, tuple) else (expected,)
    if isinstance(value, bool) and bool not in types:
        ok = False
    else:
        ok = isinstance(value, types)
    if not ok:
        names = " or ".join(TYPE_NAMES[t] for t in types)
        raise where.error(field, f"expected {names}, got {value!r}")


def load_rig(path) -> App:
    """Read and check a rig file; the App it describes."""
    path = Path(path)
    return rig_from_data(path, read_toml(path, "rig file", MAX_RIG_BYTES))


def rig_from_data(path, data: dict, base=None) -> App:
    """Check a rig given as data (a rig file's tables, as TOML reads them, from another
    format: a Wokwi diagram, ``host/rig/config/wokwi``); ``path`` is the file it came from, relative
    paths are relative to its folder (or ``base``) and messages name it. The App it describes."""
    path = Path(path)
    where = _Where(path)
    _walk(where, data, "", 0)
    if isinstance(data, dict) and "boards" in data:  # (several boards: host/rig/config/boardfile.py)
        raise where.error("[[boards]]", "a rig file with several boards: run it as a BoardSet (docs/multi-board.md)")
    where.table(data, "top level:", TABLES, required=("plant", "wiring"))
    base = Path(base) if base is not None else path.parent
    firmware = where.table(data.get("firmware", {}), "[firmware]", FIRMWARE_KEYS)
    folder = _inside(where, base, "[firmware] dir", firmware.get("dir", "."), "the rig file's folder")
    if not folder.is_dir():
        raise where.error("[firmware] dir", f"no folder {folder}")
    entry = firmware.get("entry", ENTRY)
    if not _inside(where, folder, "[firmware] entry", entry, "the firmware folder").is_file():
        found = sorted(p.name for p in folder.glob("*.py"))[:50]  # (a folder of thousands: the first 50)
        raise where.error("[firmware] entry", f"no {entry} in {folder} {unknown(entry, found, what='its .py files')}")
    default_lib = ["lib"] if (folder / "lib").is_dir() else []  # a board's /lib is on its path
    libs = tuple(_folder(where, folder, "[firmware] lib", item) for item in firmware.get("lib", default_lib))
    board_name, board_dir, pins, boards = _board(where, base, data.get("board", {}))
    platform = (_family(where, data.get("board", {})) or identity(board_name) or (None,))[0]
    pins = with_builtin_lines(pins, platform)  # (rp2's BOOTSEL, wired by name)
    if migrate.is_01(data):  # (0.1's [plant] kind: the one message names today's form)
        raise where.error("[plant] kind", migrate.message(data, path))
    try:  # ([world]: the body's world and its options)
        plant_table = with_world(data["plant"], data.get("world"))
    except PartsError as e:
        raise ConfigError(f"{where.path}: {e}") from None
    build = _parts_builder(where, plant_table)  # a body and parts (sim_plant.catalogue)
    plant = check_contract(build())
    wiring = _wiring(where, data["wiring"], pins, board_name, plant)
    rigrules.check_wiring(where, wiring, pins, plant, platform)
    rigrules.check_buses(where, plant, wiring, pins, platform)
    also = data["board"].get("also", ()) if isinstance(data.get("board"), dict) else ()
    rigrules.check_boards(where, tuple(also), wiring, known_boards(), read_pin_map)
    rigrules.check_start(where, "[plant] start_pose", plant)
    budget_specs = _budgets(where, data.get("budgets", {}), plant, wiring)
    worlds = _worlds(where, data.get("worlds", {"default": {}}), build, (wiring, pins, platform))
    interpreter = where.table(data.get("interpreter", {}), "[interpreter]", INTERPRETER_KEYS)
    name = _name(where, "name", data.get("name") or folder.name)
    faults = _faults(where, data.get("faults", []), plant)
    _tests(where, data.get("tests", {}))
    heap = [f.size for f in faults if f.kind == "heap"]  # a smaller heap is a fault too

    def make_plant(**extra):  # (as a plant class does: TypeError, ValueError for bad options)
        return with_faults(build(**extra), faults)

    return App(
        name=name,
        default_board=board_name,
        make_plant=make_plant,
        wiring=wiring,
        make_budgets=lambda plant: [build(plant) for build in budget_specs],
        doc=data.get("description", ""),
        worlds=worlds,
        rig_file=path,
        code=Code(folder, entry, libs, firmware.get("harness_lib", False), firmware.get("allow_exit", False)),
        board=BoardSettings(
            also=boards,
            folder=board_dir,
            pins=pins,
            identity=_family(where, data.get("board", {})),
            cpu=_cpu(where, data.get("board", {}), _family(where, data.get("board", {})) or identity(board_name)),
            console_baud=_console_baud(where, data.get("board", {})),
            confine=confinement(where, data.get("board", {})),
        ),
        interpreter=InterpreterSettings(
            heap_size=heap[-1] if heap else _heap_size(where, "[interpreter] heap_size", interpreter.get("heap_size")),
            ticks_wrap_s=_wrap_s(where, interpreter.get("ticks_wrap_s")),
            mpy_version=_mpy_version(where, interpreter.get("version")),
        ),
        run=RunSettings(
            faults=tuple(faults),
            console_max_bytes=_console_max_bytes(where, data.get("trace", {})),
            report=_report(where, data.get("report", {}), wiring),
        ),
    )


def _tests(where: _Where, table: dict) -> None:
    """``[tests] exclude``: patterns of the files pytest must not collect as tests."""
    for pattern in where.table(table, "[tests]", TESTS_KEYS).get("exclude", []):
        if not isinstance(pattern, str) or not pattern:
            raise where.error("[tests] exclude", f"expected file name patterns (text), got {pattern!r}")


def _report(where: _Where, table: dict, wiring: dict) -> Report:
    """``[report]``: the report's own views of this robot by name (``views``, listed in
    docs/traces.md), how its firmware prints its pose (``pose_line``) and how a
    campaign's run of it passes (``judge``: docs/campaigns.md)."""
    where.table(table, "[report]", REPORT_KEYS)
    for i, name in enumerate(table.get("views", [])):  # (ours and the rig's own: [plant] catalogue is read first)
        if not isinstance(name, str) or catalogue.resolve("views", name) is None:
            views = catalogue.views()
            shown = repr(name) if len(repr(name)) < 70 else repr(name)[:66] + "..."
            known = unknown(name, views, what="views")
            raise where.error(f"[report] views[{i}]", f"expected a view's name, got {shown} {known}")
    judge = where.table(table.get("judge", {}), "[report.judge]", JUDGE_KEYS)
    for key, hi in (("home_within_m", 1000.0), ("min_coverage", 1.0)):
        if key in judge and not 0 <= judge[key] <= hi:
            raise where.error(f"[report.judge] {key}", f"expected 0 to {hi:g}, got {judge[key]!r}")
    pose = table.get("pose_line")
    if pose is not None:
        where.table(pose, "[report.pose_line]", POSE_LINE_KEYS, required=tuple(POSE_LINE_KEYS))
        probes = [s for s in wiring.values() if s.startswith(PROBE_PREFIX)]
        if pose["probe"] not in probes:
            known = unknown(pose["probe"], probes, what="the wiring's probes")
            raise where.error("[report.pose_line] probe", f"no pin is wired to {pose['probe']!r} {known}")
        columns = pose["columns"]
        if len(columns) != 4 or not all(isinstance(c, str) and c.isidentifier() for c in columns):
            raise where.error(
                "[report.pose_line] columns", f"expected 4 names (t, x, y, heading), got {columns!r}"[:200]
            )
        pose = PoseLine(**{**pose, "columns": tuple(columns)})
    views = table.get("views")
    judged = Judge(**judge) if "judge" in table else None
    return Report(tuple(views) if views is not None else None, pose, judged)


def _walk(where: _Where, value, field: str, depth: int) -> None:
    """Every key and text in the file: no control characters (a NUL ends a C string, a
    newline a log line), at most ``MAX_DEPTH`` levels of tables and lists."""
    if depth > MAX_DEPTH:
        raise where.error(field, f"nested deeper than {MAX_DEPTH} levels of tables and lists")
    if isinstance(value, str) and not field.endswith(".marker"):  # (a marker is one byte: checked as one)
        _text(where, field, value)
    elif isinstance(value, dict):
        for key, item in value.items():
            _text(where, f"{field} {key!r}".strip(), key)
            _walk(where, item, f"{field}.{key}" if field else key, depth + 1)
    elif isinstance(value, list):
        for i, item in enumerate(value):
            _walk(where, item, f"{field}[{i}]", depth + 1)


def _text(where: _Where, field: str, text: str) -> None:
    bad = CONTROL.search(text)
    if bad:
        raise where.error(field, f"a control character ({bad.group()!r}) in {text[:60]!r}: expected plain text")


def _name(where: _Where, field: str, name) -> str:
    """A name that becomes a folder's name (a trace folder, a board's folder): one
    safe path component."""
    problem = option_table.Name().problem(name)
    if problem:
        raise where.error(field, problem)
    return name


def _inside(where: _Where, base: Path, field: str, item: str, what: str) -> Path:
    """``base / item`` resolved (links followed), refused unless it lies in ``base``."""
    path = (base / item).resolve()
    if not path.is_relative_to(base.resolve()):
        raise where.error(field, f"{item!r} is {path}, outside {what} {base.resolve()}: expected a path inside it")
    return path


def _console_max_bytes(where: _Where, trace: dict) -> int | None:
    """[trace] console_max_bytes: the console file's cap, 4 KiB to 1 TiB."""
    value = where.table(trace, "[trace]", {"console_max_bytes": int}).get("console_max_bytes")
    if value is not None and not 4096 <= value <= 2**40:
        raise where.error("[trace] console_max_bytes", f"expected 4096 to {2**40} bytes, got {value}")
    return value


def _console_baud(where: _Where, board) -> int:
    """[board] console_baud: the REPL UART's rate, at which print() takes virtual time
    (0: printing is free); 300 baud to 12 Mbaud."""
    value = board.get("console_baud", CONSOLE_BAUD) if isinstance(board, dict) else CONSOLE_BAUD
    if isinstance(value, bool) or not (value == 0 or 300 <= value <= 12_000_000):
        raise where.error("[board] console_baud", f"expected 0 (off) or 300 to 12000000 baud, got {value!r}")
    return value


def _cpu(where: _Where, board, identity: tuple[str, str] | None) -> str:
    """[board] cpu: the CPU whose time the firmware's compute costs ("rp2040@125MHz", ...,
    "free": none), by default the family's (host/rig/targets/mcutime.py, docs/mcu-time.md)."""
    default = mcutime.default_cpu(identity)
    value = board.get("cpu", default) if isinstance(board, dict) else default
    problem = mcutime.check_cpu(value)
    if problem:
        raise where.error("[board] cpu", problem)
    return value


def _faults(where: _Where, entries: list, plant) -> tuple:
    """``[[faults]]``: the fault schedule (sim_plant/faults.py), checked against the plant."""
    try:
        faults = parse_faults(entries)
        with_faults(plant, faults)
    except FaultError as e:
        raise where.error("[[faults]]", str(e)) from None
    for fault in faults:
        if fault.kind == "heap":
            _heap_size(where, "[[faults]] (heap) size", fault.size)
    return faults


def _family(where: _Where, board) -> tuple[str, str] | None:
    """[board] family = "esp32" | "rpi_pico": the chip the firmware sees in sys.platform
    (a board named after one of them needs no family)."""
    family = board.get("family") if isinstance(board, dict) else None
    if family is None:
        return None
    if family not in IDENTITIES:
        known = ", ".join(IDENTITIES)
        raise where.error(
            "[board] family", f"unknown family {family!r} (known: {known}){_did_you_mean(family, list(IDENTITIES))}"
        )
    return IDENTITIES[family]


def _heap_size(where: _Where, field: str, size: str | int | None) -> str | None:
    """The firmware's heap: bytes (an integer, or text like ``192K``, ``2M``, ``0x30000``,
    ``24wK``, as ``-X heapsize`` reads them), from 48K to 1G."""
    if size is None:
        return None
    size_bytes = heap_bytes(size)
    expected = f"expected bytes from {HEAP_MIN_BYTES // 1024}K to {HEAP_MAX_BYTES >> 20}M, like 192K or 2M"
    if size_bytes is None:
        raise where.error(field, f"{expected}, got {size!r}")
    if not HEAP_MIN_BYTES <= size_bytes <= HEAP_MAX_BYTES:
        least = "a firmware hardly starts in less" if size_bytes < HEAP_MIN_BYTES else "more than a board has"
        raise where.error(field, f"{expected} ({least}), got {size!r} ({size_bytes} bytes)")
    return str(size)


def _wrap_s(where: _Where, seconds) -> float | None:
    if seconds is not None and not 0 <= seconds <= 1000:
        raise where.error("[interpreter] ticks_wrap_s", f"expected 0 to 1000 s (the ticks' period), got {seconds}")
    return None if seconds is None else float(seconds)


def _mpy_version(where: _Where, version: str | None) -> str | None:
    """``[interpreter] version``: the MicroPython the board runs, one the harness builds
    (host/core/interpreter.py RELEASES, docs/versions.md)."""
    if version is None:
        return None
    from host.core import interpreter

    try:
        return interpreter.release(version).version
    except SetupError as e:
        raise where.error("[interpreter] version", str(e)) from None


def _folder(where: _Where, base: Path, field: str, item) -> Path:
    _check_type(where, field, item, str)
    folder = _inside(where, base, field, item, "the firmware folder")
    if not folder.is_dir():
        raise where.error(field, f"no folder {folder}")
    return folder


def _board(where: _Where, base: Path, board: dict):
    """(name, folder holding board.py or None, pins, boards the app runs on)."""
    if isinstance(board, str):
        board = {"name": board}
    where.table(board, "[board]", BOARD_KEYS)
    given = [k for k in ("name", "file", "pins") if k in board]
    if len(given) != 1:
        raise where.error("[board]", f"expected one of name, file or pins, got {', '.join(given) or 'none'}")
    also = tuple(_name(where, "[board] also", name) for name in board.get("also", ()))
    if "pins" in board:
        pins = board["pins"]
        highest = rigrules.highest_pin(IDENTITIES.get(board.get("family"), (None,))[0])
        for pin, value in pins.items():
            _pin(where, f"[board.pins] {pin}", value, highest)
        return "pins", None, dict(pins), also
    if "file" in board:
        path = _inside(where, base, "[board] file", board["file"], "the rig file's folder")
        field = "[board] file"
    else:
        path = BOARDS_DIR / _name(where, "[board] name", board["name"]) / "board.py"
        field = "[board] name"
        if not path.is_file():
            known = unknown(board["name"], known_boards(), what="boards")
            raise where.error(field, f"no board {board['name']!r} {known}")
    try:
        pins = read_board_file(path)
    except ConfigError as e:
        raise where.error(field, str(e)) from None
    name = board.get("name") or path.parent.name
    return name, path.parent, pins, (name, *also) if "name" in board else also


def _pin(where: _Where, field: str, value, highest: int) -> None:
    """A pin: its number on the board (0 to the family's highest GPIO), or the name the
    code gives ``Pin("GP14")``."""
    _check_type(where, field, value, (int, str))
    if isinstance(value, int) and not 0 <= value <= highest:
        raise where.error(field, f"expected a pin number from 0 to {highest}, got {value}")
    if isinstance(value, str) and not option_table.SAFE_NAME.fullmatch(value):
        raise where.error(field, f"expected a pin name of letters, digits, '_', '.', '+' or '-', got {value!r}")


def _parts_builder(where: _Where, table: dict):
    """``[plant] body = ...`` with ``[[plant.parts]]``: a function building the plant
    with a world's or ``--param``'s body options over the table's (ValueError naming the
    field); the table itself is checked here (a ConfigError naming the file)."""

    def build(**opts):
        return assemble({**table, **opts}, base=where.path.parent, rig_file=where.path)

    try:
        build()
    except PartsError as e:
        raise ConfigError(f"{where.path}: {e}") from None
    return build


def _wiring(where: _Where, wiring: dict, pins: dict, board: str, plant) -> dict[str, str]:
    signals = {**plant.inputs, **plant.outputs}
    for pin, signal in wiring.items():
        field = f"[wiring] {pin}"
        _check_type(where, field, signal, str)
        if pin not in pins:
            raise where.error(field, f"board {board} has no pin named {pin} {unknown(pin, pins, what='pins')}")
        if signal in plant.tied_chip_selects():
            raise where.error(
                field,
                f'expected a plant signal, got {signal!r}, a chip select the rig ties low (cs = "low" in '
                f"[[plant.parts]] {signal.rpartition('.')[0]}): wire a pin to it or tie it low, not both",
            )
        if not signal.startswith(PROBE_PREFIX) and signal not in signals:
            close = unknown(signal, signals, what="signals").rpartition(")")[2]
            raise where.error(
                field,
                f"the plant has no signal {signal!r} (inputs: {', '.join(plant.inputs)}; "
                f"outputs: {', '.join(plant.outputs)}; or probe:<name> for a pin only the harness watches){close}",
            )
    by_pin: dict = {}
    for pin in wiring:
        other = by_pin.setdefault(str(pins[pin]), pin)
        if other != pin:
            raise where.error(f"[wiring] {pin}", f"pin {pins[pin]} is {other} too: one pin can be wired once")
    return dict(wiring)


def _budgets(where: _Where, budgets: dict, plant, wiring: dict) -> list:
    """One builder per budget: ``build(plant) -> Budget``; each is tried once here, on
    the rig file's own plant, so that its mistakes show before a run."""
    builders = []
    for name, spec in budgets.items():
        field = f"[budgets.{name}]"
        _name(where, field, name)
        if not isinstance(spec, dict):
            raise where.error(field, f"expected a table, got {spec!r}")
        budget_kind = spec.get("kind")
        if not isinstance(budget_kind, str) or budget_kind not in budgets_of.KINDS:
            hint = _did_you_mean(str(budget_kind), budgets_of.KINDS)
            kinds = ", ".join(budgets_of.KINDS)
            raise where.error(f"{field} kind", f"expected one of {kinds}, got {budget_kind!r}{hint}")
        cls = budgets_of.KINDS[budget_kind]  # (its schema: host/rig/config/budgets.py)
        keys, required = cls.rig_keys(spec)
        where.table(spec, field, keys, required=list(required))
        sources = [("source", spec.get("source"))] + [("sources", s) for s in spec.get("sources", [])]
        if cls.ON_BUS:
            _bus_source(where, field, plant, spec)
            sources = [("ready", spec.get("ready"))]
        for key, signal in sources:
            if signal is None:
                continue
            _check_type(where, f"{field} {key}", signal, str)
            if signal.startswith(PROBE_PREFIX) and signal not in wiring.values():
                raise where.error(f"{field} {key}", f"no pin is wired to {signal!r}: the budget would measure nothing")
            if not signal.startswith(PROBE_PREFIX) and signal not in {**plant.inputs, **plant.outputs}:
                known = unknown(signal, [*plant.inputs, *plant.outputs], what="signals")
                raise where.error(f"{field} {key}", f"the plant has no signal {signal!r} {known}")
        for key, (least, most) in cls.BOUNDS.items():
            if isinstance(spec.get(key), int) and not least <= spec[key] <= most:
                raise where.error(f"{field} {key}", f"expected {least} to {most} microseconds, got {spec[key]}")
        marker = spec.get("marker")
        if marker is not None and not (len(marker) == 1 and 0 < ord(marker) < 128):
            raise where.error(f"{field} marker", f"expected one character of one byte (ASCII, not NUL), got {marker!r}")
        build = _budget_builder(where, field, name, cls, spec)
        build(plant)
        builders.append(build)
    return builders


def _budget_builder(where: _Where, field: str, name: str, cls, spec: dict):
    def build(plant):
        args = {k: spec[k] for k in spec if k not in ("kind", "description")}
        if cls.PERIOD_FROM_PLANT and "period_us" not in args:
            args["period_us"] = _sample_period(where, field, plant, spec["source"])
        if "marker" in args:
            args["marker"] = args["marker"].encode()
        source = args.pop("sources", None) or args.pop("source", None)
        budget = cls(name, tuple(source) if isinstance(source, list) else source or "compute", **args)
        names = {k: getattr(budget, k) for k in ("period_us", "tolerance_us", "limit_us") if hasattr(budget, k)}
        names.update({k.replace("_us", "_ms"): v / 1000 for k, v in names.items()})
        try:
            budget.description = spec.get("description", "").format(**names)
        except (KeyError, ValueError) as e:
            raise where.error(f"{field} description", f"cannot fill in {e} (fields: {', '.join(names)})") from None
        return budget

    return build


def _bus_source(where: _Where, field: str, plant, spec: dict) -> None:
    """A bus budget's source is a bus one of the plant's devices is on; its ``address``
    one of a device on that bus (an SPI bus's devices have none: chip selects); its
    ``register`` one of 256: else the budget could never match a transfer."""
    devices = plant.bus_devices()
    buses = sorted({d.bus for d in devices})
    if spec["source"] not in buses:
        known = unknown(spec["source"], buses, what="buses")
        raise where.error(f"{field} source", f"no device of the plant is on bus {spec['source']!r} {known}")
    if "address" in spec:
        at = {d.address: d.label for d in devices if d.bus == spec["source"] and d.address is not None}
        if spec["address"] not in at:
            known = ", ".join(f"0x{a:02x} ({n})" for a, n in sorted(at.items())) or "none: SPI devices are selected"
            raise where.error(
                f"{field} address",
                f"no device on bus {spec['source']} at {spec['address']!r}: the budget would match no transfer "
                f"(addresses on it: {known})",
            )
    register = spec.get("register")
    if register is not None and not 0 <= register <= 0xFF:
        raise where.error(f"{field} register", f"expected a register from 0 to 255 (0xff), got {register}")


def _sample_period(where: _Where, field: str, plant, source: str) -> int:
    period = plant.sample_period_us(source)
    if period is None:
        what = (
            "a probe has no period of its own"
            if source.startswith(PROBE_PREFIX)
            else f"the plant samples {source} at no fixed period"
        )
        raise where.error(f"{field} period_us", f"missing, and {what}: give it in microseconds")
    return period


def _worlds(where: _Where, worlds: dict, build, board) -> dict[str, dict]:
    """Each world's options, checked by building its plant (and that plant against the
    rules of ``host/rig/config/rigrules.py``: its buses, its start pose; ``board``: (wiring,
    pins, platform))."""
    wiring, pins, platform = board
    for name, world in worlds.items():
        field = f"[worlds.{name}]"
        _name(where, field, name)
        if not isinstance(world, dict):
            raise where.error(field, f"expected a table of plant options, got {world!r}")
        try:  # a body's options (and <part>.<option>) over the [plant] table's
            plant = build(**world)
        except ValueError as e:
            raise where.error(field, str(e)) from None
        if world:
            rigrules.check_buses(_Within(where, field), plant, wiring, pins, platform)
            rigrules.check_start(where, f"{field} start_pose", plant)
    return {name: dict(world) for name, world in worlds.items()} or {"default": {}}
