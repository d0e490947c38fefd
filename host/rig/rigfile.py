"""Rig files: a firmware folder's test rig as data (TOML, ``docs/rig-file.md``).

A rig file names the firmware (folder, entry file, library folders), the board (a board
file or a pins table), the plant (a kind from :mod:`sim_plant.kinds` with options), the
wiring (board pin -> plant signal), the timing budgets, the named worlds and interpreter
settings. It is checked whole before anything starts: every mistake raises a
:class:`~host.core.errors.ConfigError` that names the file and the field. Our own apps
are rig files too (``firmware/apps/<app>/rig*.toml``).
"""

import difflib
from pathlib import Path

import tomllib

from host.core.errors import ConfigError
from host.core.paths import BOARDS_DIR
from host.rig.app import App
from host.rig.boards import IDENTITIES, known_boards, read_board_file
from host.rig.budgets import ComputeBudget, LatencyBudget, PeriodBudget, PulseBudget
from host.rig.wiring import PROBE_PREFIX
from sim_plant import kinds
from sim_plant.faults import FaultError, parse_faults, with_faults

TABLES = {
    "name": str,
    "description": str,
    "firmware": dict,
    "board": dict,
    "plant": dict,
    "wiring": dict,
    "budgets": dict,
    "worlds": dict,
    "interpreter": dict,
    "faults": list,
    "trace": dict,
}
FIRMWARE_KEYS = {"dir": str, "entry": str, "lib": list, "harness_lib": bool}
BOARD_KEYS = {"name": str, "file": str, "pins": dict, "also": list, "family": str}
PLANT_KEYS = {"kind": str, "options": dict}
INTERPRETER_KEYS = {"heap_size": str, "ticks_wrap_s": (int, float)}
BUDGET_KINDS = {
    "period": (PeriodBudget, {"source": str, "period_us": (int, str), "tolerance_us": int, "marker": str}),
    "latency": (LatencyBudget, {"source": str, "limit_us": int}),
    "pulse": (PulseBudget, {"sources": list, "limit_us": int}),
    "compute": (ComputeBudget, {"limit_us": int}),
}
COMMON_BUDGET_KEYS = {"kind": str, "description": str}
TYPE_NAMES = {str: "text", int: "an integer", float: "a number", bool: "true/false", list: "a list", dict: "a table"}


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
    where = _Where(path)
    if not path.is_file():
        raise ConfigError(f"{path}: no such rig file")
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as e:
        raise ConfigError(f"{path}: not valid TOML: {e}") from None
    where.table(data, "top level:", TABLES, required=("plant", "wiring"))
    base = path.parent
    firmware = where.table(data.get("firmware", {}), "[firmware]", FIRMWARE_KEYS)
    folder = (base / firmware.get("dir", ".")).resolve()
    if not folder.is_dir():
        raise where.error("[firmware] dir", f"no folder {folder}")
    entry = firmware.get("entry", "main.py")
    if not (folder / entry).is_file():
        raise where.error("[firmware] entry", f"no {entry} in {folder}")
    default_lib = ["lib"] if (folder / "lib").is_dir() else []  # a board's /lib is on its path
    libs = tuple(_folder(where, folder, "[firmware] lib", item) for item in firmware.get("lib", default_lib))
    board_name, board_dir, pins, boards = _board(where, base, data.get("board", {}))
    kind, options = _plant(where, data["plant"])
    _check_options(where, "[plant.options]", kind, options)
    plant = _make_plant(where, kind, options, "[plant.options]")
    wiring = _wiring(where, data["wiring"], pins, board_name, plant)
    budget_specs = _budgets(where, data.get("budgets", {}), plant, kind, wiring)
    worlds = _worlds(where, data.get("worlds", {"default": {}}), kind, options)
    interpreter = where.table(data.get("interpreter", {}), "[interpreter]", INTERPRETER_KEYS)
    name = data.get("name") or folder.name
    faults = _faults(where, data.get("faults", []), plant)
    heap = [f.size for f in faults if f.kind == "heap"]  # a smaller heap is a fault too

    def make_plant(**extra):  # (as a plant class does: TypeError, ValueError for bad options)
        return with_faults(kinds.make(kind, **{**options, **extra}), faults)

    return App(
        name=name,
        default_board=board_name,
        make_plant=make_plant,
        wiring=wiring,
        make_budgets=lambda plant: [build(plant) for build in budget_specs],
        boards=boards,
        doc=data.get("description", ""),
        folder=folder,
        worlds=worlds,
        entry=entry,
        lib_dirs=libs,
        harness_lib=firmware.get("harness_lib", False),
        board_dir=board_dir,
        pins=pins,
        rig_file=path,
        plant_kind=kind,
        plant_options=dict(options),
        heap_size=heap[-1] if heap else _heap_size(where, interpreter.get("heap_size")),
        ticks_wrap_s=_wrap_s(where, interpreter.get("ticks_wrap_s")),
        identity=_family(where, data.get("board", {})),
        extra={"faults": faults},
        console_max_bytes=_console_max_bytes(where, data.get("trace", {})),
    )


def _console_max_bytes(where: _Where, trace: dict) -> int | None:
    """[trace] console_max_bytes: the console file's cap, 4 KiB to 1 TiB."""
    value = where.table(trace, "[trace]", {"console_max_bytes": int}).get("console_max_bytes")
    if value is not None and not 4096 <= value <= 2**40:
        raise where.error("[trace] console_max_bytes", f"expected 4096 to {2**40} bytes, got {value}")
    return value


def _faults(where: _Where, entries: list, plant) -> tuple:
    """``[[faults]]``: the fault schedule (sim_plant/faults.py), checked against the plant."""
    try:
        faults = parse_faults(entries)
        with_faults(plant, faults)
    except FaultError as e:
        raise where.error("[[faults]]", str(e)) from None
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


def _heap_size(where: _Where, text: str | None) -> str | None:
    import re

    if text is not None and not re.fullmatch(r"[1-9][0-9]*[KkMm]?", text):
        raise where.error("[interpreter] heap_size", f"expected bytes like 192K or 2M, got {text!r}")
    return text


def _wrap_s(where: _Where, seconds) -> float | None:
    if seconds is not None and not 0 <= seconds <= 1000:
        raise where.error("[interpreter] ticks_wrap_s", f"expected 0 to 1000 s (the ticks' period), got {seconds}")
    return None if seconds is None else float(seconds)


def _folder(where: _Where, base: Path, field: str, item) -> Path:
    _check_type(where, field, item, str)
    folder = (base / item).resolve()
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
    also = tuple(board.get("also", ()))
    if "pins" in board:
        pins = board["pins"]
        for pin, value in pins.items():
            _check_type(where, f"[board.pins] {pin}", value, (int, str))
        return "pins", None, dict(pins), also
    if "file" in board:
        path = (base / board["file"]).resolve()
        field = "[board] file"
    else:
        path = BOARDS_DIR / board["name"] / "board.py"
        field = "[board] name"
        if not path.is_file():
            known, hint = ", ".join(known_boards()), _did_you_mean(board["name"], known_boards())
            raise where.error(field, f"no board {board['name']!r} (known: {known}){hint}")
    try:
        pins = read_board_file(path)
    except ConfigError as e:
        raise where.error(field, str(e)) from None
    name = board.get("name") or path.parent.name
    return name, path.parent, pins, (name, *also) if "name" in board else also


def _plant(where: _Where, plant: dict):
    where.table(plant, "[plant]", PLANT_KEYS, required=("kind",))
    kind = plant["kind"]
    if kind not in kinds.KINDS:
        hint = _did_you_mean(kind, kinds.KINDS)
        raise where.error("[plant] kind", f"unknown plant kind {kind!r} (kinds: {', '.join(kinds.KINDS)}){hint}")
    return kind, dict(plant.get("options", {}))


def _check_options(where: _Where, field: str, kind: str, options: dict) -> None:
    """Option names, and their types against the defaults' (a number where the default is
    one, a list of numbers where it is a pose or a pair)."""
    known = kinds.options(kind)
    for name, value in options.items():
        if name not in known:
            hint = _did_you_mean(name, known)
            raise where.error(
                f"{field} {name}", f"the {kind} plant has no such option (options: {', '.join(known)}){hint}"
            )
        _check_like(where, f"{field} {name}", value, known[name])


def _check_like(where: _Where, field: str, value, default) -> None:
    number = (int, float)
    if isinstance(default, bool) or isinstance(value, bool):
        if isinstance(default, bool) and not isinstance(value, bool):
            raise where.error(field, f"expected true/false, got {value!r}")
        return
    if isinstance(default, number) and not isinstance(value, number):
        raise where.error(field, f"expected a number, got {value!r}")
    if isinstance(default, str) and not isinstance(value, str):
        raise where.error(field, f"expected text, got {value!r}")
    if isinstance(default, tuple) and default and all(isinstance(v, number) for v in default):
        if not (isinstance(value, list) and len(value) == len(default) and all(_is_number(v) for v in value)):
            raise where.error(field, f"expected a list of {len(default)} numbers, got {value!r}")


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _make_plant(where: _Where, kind: str, options: dict, field: str):
    try:
        return kinds.make(kind, **options)
    except (TypeError, ValueError) as e:
        raise where.error(field, f"the {kind} plant refuses it: {e}") from None


def _wiring(where: _Where, wiring: dict, pins: dict, board: str, plant) -> dict[str, str]:
    signals = {**plant.inputs, **plant.outputs}
    for pin, signal in wiring.items():
        field = f"[wiring] {pin}"
        _check_type(where, field, signal, str)
        if pin not in pins:
            raise where.error(field, f"board {board} has no pin named {pin} (pins: {', '.join(pins)})")
        if not signal.startswith(PROBE_PREFIX) and signal not in signals:
            raise where.error(
                field,
                f"the plant has no signal {signal!r} (inputs: {', '.join(plant.inputs)}; "
                f"outputs: {', '.join(plant.outputs)}; or probe:<name> for a pin only the harness watches)",
            )
    by_pin: dict = {}
    for pin in wiring:
        other = by_pin.setdefault(str(pins[pin]), pin)
        if other != pin:
            raise where.error(f"[wiring] {pin}", f"pin {pins[pin]} is {other} too: one pin can be wired once")
    return dict(wiring)


def _budgets(where: _Where, budgets: dict, plant, kind: str, wiring: dict) -> list:
    """One builder per budget: ``build(plant) -> Budget``; each is tried once here, on
    the rig file's own plant, so that its mistakes show before a run."""
    builders = []
    for name, spec in budgets.items():
        field = f"[budgets.{name}]"
        if not isinstance(spec, dict):
            raise where.error(field, f"expected a table, got {spec!r}")
        budget_kind = spec.get("kind")
        if budget_kind not in BUDGET_KINDS:
            hint = _did_you_mean(str(budget_kind), BUDGET_KINDS)
            raise where.error(f"{field} kind", f"expected one of {', '.join(BUDGET_KINDS)}, got {budget_kind!r}{hint}")
        cls, keys = BUDGET_KINDS[budget_kind]
        optional = ("marker", "period_us") if budget_kind == "period" else ()  # period: the plant's own by default
        where.table(spec, field, {**COMMON_BUDGET_KEYS, **keys}, required=[k for k in keys if k not in optional])
        for key, signal in [("source", spec.get("source"))] + [("sources", s) for s in spec.get("sources", [])]:
            if signal is None:
                continue
            _check_type(where, f"{field} {key}", signal, str)
            if signal.startswith(PROBE_PREFIX) and signal not in wiring.values():
                raise where.error(f"{field} {key}", f"no pin is wired to {signal!r}: the budget would measure nothing")
            if not signal.startswith(PROBE_PREFIX) and signal not in {**plant.inputs, **plant.outputs}:
                known = ", ".join([*plant.inputs, *plant.outputs])
                raise where.error(f"{field} {key}", f"the plant has no signal {signal!r} (signals: {known})")
        for key in ("period_us", "limit_us", "tolerance_us"):
            if isinstance(spec.get(key), int) and (spec[key] < 0 or (spec[key] == 0 and key != "tolerance_us")):
                least = "0 or more" if key == "tolerance_us" else "more than 0"
                raise where.error(f"{field} {key}", f"expected {least} microseconds, got {spec[key]}")
        build = _budget_builder(where, field, name, cls, spec, kind)
        build(plant)
        builders.append(build)
    return builders


def _budget_builder(where: _Where, field: str, name: str, cls, spec: dict, kind: str):
    def value(plant, key):
        v = spec[key]
        if isinstance(v, str):  # "plant.<option>": the plant's own figure
            option = v.removeprefix("plant.")
            known = kinds.options(kind)
            if not v.startswith("plant.") or option not in known:
                us_options = ", ".join(f"plant.{k}" for k in known if k.endswith("_us"))
                raise where.error(f"{field} {key}", f"expected microseconds or one of {us_options}; got {v!r}")
            got = getattr(plant, option, None)
            if not _is_number(got):
                raise where.error(f"{field} {key}", f"the {kind} plant keeps no figure for {option}")
            return int(got)
        return v

    def build(plant):
        args = {k: value(plant, k) if k.endswith("_us") else spec[k] for k in spec if k not in ("kind", "description")}
        if cls is PeriodBudget and "period_us" not in args:
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


def _worlds(where: _Where, worlds: dict, kind: str, options: dict) -> dict[str, dict]:
    for name, world in worlds.items():
        field = f"[worlds.{name}]"
        if not isinstance(world, dict):
            raise where.error(field, f"expected a table of plant options, got {world!r}")
        _check_options(where, field, kind, world)
        _make_plant(where, kind, {**options, **world}, field)
    return {name: dict(world) for name, world in worlds.items()} or {"default": {}}


STARTER = """\
# The test rig of {name}: this folder's firmware on a simulated robot (docs/rig-file.md).
# Check it with `mpy-fil check {path}`; run it with `mpy-fil run {path}`.
name = "{name}"

[firmware]
entry = "{entry}"          # what runs after boot.py
# lib = ["lib"]            # library folders of your own
# harness_lib = false      # the harness's own drivers (firmware/lib): off unless you ask

[board.pins]               # the pin numbers your code uses, by a name of your choice
{pins}
[plant]
kind = "two_wheel"         # mpy-fil list: kinds, their options and their signals

[plant.options]
bridge = "tb6612"          # tb6612 | l298n | drv8833 | dir_pwm
encoder = "quadrature"     # quadrature | single | none
ranger = "hcsr04"          # hcsr04 | analog | none
# buttons = ["start"]
# presses = [["start", 1.0, 1.2]]   # name, pressed at s, released at s

[wiring]                   # pin name = plant signal (mpy-fil check lists them), or probe:<name>
{wiring}
# [budgets.loop]           # a timing budget: a pin toggled once per loop, every 50 ms
# kind = "period"
# source = "probe:loop"
# period_us = 50_000
# tolerance_us = 1_000
"""


def starter(folder: Path) -> str:
    """A commented starting rig file for a firmware folder: its entry file, and the pins
    its code passes to ``Pin(...)`` (by their constant's name when it has one), ready to
    wire."""
    files = sorted(folder.glob("*.py"))
    entry = "main.py" if (folder / "main.py").is_file() or not files else files[0].name
    trees = [tree for tree in map(_parse, sorted(folder.rglob("*.py"))) if tree is not None]
    drivers = _drivers(trees)
    pins: dict[str, int] = {}
    for tree in trees:
        pins.update(_pins_used(tree, drivers))
    lines = "".join(f"{name} = {number}\n" for name, number in sorted(pins.items(), key=lambda kv: kv[1]))
    wiring = "".join(f'# {name} = "..."\n' for name, _ in sorted(pins.items(), key=lambda kv: kv[1]))
    return STARTER.format(
        name=folder.resolve().name,
        path=folder / "rig.toml",
        entry=entry,
        pins=lines or "# LED = 25\n",
        wiring=wiring or '# LED = "probe:led"\n',
    )


def _int_constants(tree) -> dict[str, int]:
    """Module-level ``NAME = 16``, ``A, B = 16, 17`` and ``NAME = const(16)``."""
    import ast

    constants: dict[str, int] = {}
    for node in tree.body:
        if not isinstance(node, ast.Assign):
            continue
        for target in node.targets:
            names = target.elts if isinstance(target, ast.Tuple) else [target]
            values = node.value.elts if isinstance(node.value, ast.Tuple) else [node.value]
            for name, value in zip(names, values):
                if isinstance(value, ast.Call) and value.args:  # const(16)
                    value = value.args[0]
                if isinstance(name, ast.Name) and isinstance(value, ast.Constant) and type(value.value) is int:
                    constants[name.id] = value.value
    return constants


def _calls(node, name: str):
    """The calls of ``name(...)`` or ``x.name(...)`` under an AST node."""
    import ast

    for call in ast.walk(node):
        func = getattr(call, "func", None)
        if isinstance(call, ast.Call) and getattr(func, "id", getattr(func, "attr", "")) == name:
            yield call


def _parse(source: Path):
    import ast

    try:
        return ast.parse(source.read_text(errors="replace"))
    except SyntaxError:
        return None


def _drivers(trees) -> list[str]:
    """Classes that make a Pin of what they are given (``Motor(PWMA, AIN1, AIN2)``), in
    any file of the folder (a driver in lib/)."""
    import ast

    return [c.name for tree in trees for c in tree.body if isinstance(c, ast.ClassDef) and any(_calls(c, "Pin"))]


def _pins_used(tree, drivers: list[str]) -> dict[str, int]:
    """Name -> pin number for every ``Pin(n)``, ``Pin(NAME)`` and driver call in a file."""
    import ast

    constants = _int_constants(tree)
    found: dict[str, int] = {}
    for name in ["Pin", *drivers]:
        for call in _calls(tree, name):
            for arg in call.args[:1] if name == "Pin" else call.args:
                if isinstance(arg, ast.Constant) and type(arg.value) is int:  # Pin(14), TB6612(16, 17, 18)
                    found[f"PIN_{arg.value}"] = arg.value
                elif isinstance(arg, ast.Name) and arg.id in constants:
                    found[arg.id] = constants[arg.id]
    return found
