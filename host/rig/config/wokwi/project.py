"""A Wokwi project folder as a rig: ``rig_from_project(folder)`` gives the same App a rig
file gives (:func:`host.rig.config.rigfile.load_rig`), each part named by its diagram ``id``;
``rig_text(folder)`` the equivalent rig file, commented, which ``mpy-fil import-wokwi``
writes (``docs/wokwi.md``).

The folder holds ``diagram.json``, the MicroPython code (``main.py``, its modules, a
``lib/``) and maybe a ``wokwi.toml``. The code is read, not run, for what the diagram
cannot say: which pins it drives with PWM (an LED's duty) and which I2C bus it makes on
a chip's SDA and SCL (``I2C(0)`` or ``SoftI2C``)."""

import difflib
import re
from pathlib import Path

import tomllib

from host.core import safefs
from host.core.errors import ConfigError
from host.core.nesting import too_deep
from host.rig.config.app import App
from host.rig.config.rigfile import rig_from_data
from host.rig.config.wokwi import parts as table
from host.rig.config.wokwi.boards import BOARD_ATTRS
from host.rig.config.wokwi.diagram import read_diagram
from host.rig.config.wokwi.tomlout import rig_toml
from host.rig.scan.pinscan import scan_folder

DIAGRAM = "diagram.json"
WOKWI_KEYS = {"version", "firmware", "elf", "gdbServerPort", "rfc2217ServerPort"}
WOKWI_TABLES = {"wokwi", "net"}  # [[chip]] (custom chips) is refused
ENTRY = "main.py"


def is_project(path: Path) -> bool:
    """A Wokwi project: a folder with a diagram.json and no rig.toml, or a diagram.json."""
    path = Path(path)
    if path.name == DIAGRAM:
        return path.is_file()
    return (path / DIAGRAM).is_file() and not (path / "rig.toml").is_file()


def rig_from_project(folder) -> App:
    """The rig of a Wokwi project folder (or its diagram.json): the App ``load_rig``
    would give for the rig file ``import-wokwi`` writes."""
    folder = _folder(folder)
    data, _notes = rig_data(folder)
    return rig_from_data(folder / DIAGRAM, data, base=code_folder(folder))


def rig_text(folder) -> str:
    """The project's rig file, commented (what ``mpy-fil import-wokwi`` writes)."""
    folder = _folder(folder)
    data, notes = rig_data(folder)
    rig_from_data(rig_path(folder), data)  # (what is written must load)
    return rig_toml(data, notes)


def code_folder(folder: Path) -> Path:
    """Where the project's ``main.py`` is: the project folder, or the folder above it when
    the project is one board's folder of Wokwi's MicroPython template (``esp32/diagram.json``,
    ``esp32/wokwi.toml``, ... and one ``main.py`` at the repository's root, which mpremote
    puts on the board: github.com/wokwi/wokwi-vscode-micropython)."""
    if safefs.regular_file(folder / ENTRY):
        return folder
    up = folder.resolve().parent
    if safefs.regular_file(up / ENTRY) and not (up / DIAGRAM).is_file():
        return up
    return folder


def rig_path(folder: Path) -> Path:
    """The rig file ``import-wokwi`` writes: ``rig.toml`` beside the diagram, or, for a
    board's folder of Wokwi's template, ``rig-<board folder>.toml`` beside ``main.py`` (a rig
    file's firmware lies in its own folder)."""
    code = code_folder(folder)
    return folder / "rig.toml" if code == folder else code / f"rig-{folder.resolve().name}.toml"


def import_wokwi(folder, force: bool = False) -> Path:
    """Write the project's rig file (:func:`rig_path`); an existing one only with ``force``."""
    folder = _folder(folder)
    text = rig_text(folder)
    path = rig_path(folder)
    safefs.refuse_link(path)  # (--force replaces a file, never what a link points to)
    if path.exists() and not force:
        raise ConfigError(f"{path}: exists: expected --force to overwrite it")
    safefs.write_text(path, text, refuse_links=True)
    return path


def _folder(path) -> Path:
    path = Path(path)
    folder = path.parent if path.name == DIAGRAM else path
    if not (folder / DIAGRAM).is_file():
        raise ConfigError(f"{folder}: no {DIAGRAM}: expected a Wokwi project folder")
    if not safefs.regular_file(code_folder(folder) / ENTRY):
        raise ConfigError(
            f"{folder}: no {ENTRY}: a Wokwi MicroPython project runs main.py (looked in {folder} and, as "
            f"Wokwi's MicroPython template keeps it, in the folder above, {folder.resolve().parent})"
        )
    return folder


def rig_data(folder: Path) -> tuple[dict, dict]:
    """The rig as data (a rig file's tables) and the comments of each part (by id, and
    ``"board"``)."""
    diagram = read_diagram(folder / DIAGRAM)
    _check_wokwi_toml(folder)
    board = diagram.board
    _check_board_attrs(diagram)
    code = code_folder(folder)
    libs = (code / "lib",) if (code / "lib").is_dir() else ()
    scan = scan_folder(code, libs, None, ENTRY, "rp2" if board.family == "rpi_pico" else None)
    pwm = {int(u.key) for u in scan.uses if u.kind == "pwm" and u.key.isdigit()}
    ctx = table.Context(diagram, board.family, pwm, dict(scan.buses))
    pins, wiring, entries = {}, {}, []
    notes = {"board": [f"{board.title} ({board.wokwi}, part {diagram.board_part.id!r}): the {board.family} family"]}
    if code != folder:  # (Wokwi's MicroPython template: a folder per board, main.py at the root)
        notes["board"].append(f"diagram: {folder.resolve().name}/{DIAGRAM}; firmware: {code / ENTRY}")
    for part in diagram.parts:
        pmap = table.mapper(part)
        mapped = pmap.build(part, ctx)
        _merge(diagram, part, mapped, pins, wiring)
        if mapped.entry is not None:
            entries.append(mapped.entry)
        notes[part.id] = [f"{part.type}", *mapped.notes]
    plant = {"body": "desk" if ctx.sonars else "bench", **_desk(ctx.sonars), "parts": entries}
    data = {
        "name": _name(folder),
        "description": f"the Wokwi project {folder.name}: {board.title}, {len(entries)} parts",
        "firmware": {"dir": ".", "entry": ENTRY},
        "board": {"family": board.family, "pins": pins},
        "plant": plant,
        "wiring": wiring,
    }
    return data, notes


def _merge(diagram, part, mapped, pins: dict, wiring: dict) -> None:
    """A part's pins into the rig's: a pin wired to two parts is refused, unless one of
    them is a logic analyser's probe (the trace records the pin anyway: the part keeps it)."""
    for key, gpio in mapped.pins.items():
        signal = mapped.wiring[key]
        if key in pins and not (signal.startswith("probe:") or wiring[key].startswith("probe:")):
            raise ConfigError(f"{diagram.path}: {part.where()}: {key} is wired to {wiring[key]} too: one part a pin")
        if key in pins and signal.startswith("probe:"):
            mapped.notes.append(f"{key} is {wiring[key]}'s pin: the trace records it as such")
            continue
        pins[key] = gpio
        wiring[key] = signal


def _desk(sonars: list) -> dict:
    """The desk's room: each HC-SR04 in its lane, a box at its distance."""
    if not sonars:
        return {}
    depth_m, width_m = table.SONAR_BOX_M
    y0_m = 1.0
    boxes = [
        [round(table.DESK_X_M + d_m + depth_m / 2, 4), y0_m + k * table.LANE_M, depth_m, width_m]
        for k, (_id, d_m) in enumerate(sonars)
    ]
    return {
        "room_w_m": table.DESK_X_M + table.SONAR_MAX_RANGE_M + 1.0,
        "room_h_m": 2 * y0_m + (len(sonars) - 1) * table.LANE_M,
        "start_pose": [table.DESK_X_M, y0_m, 0.0],
        "obstacles": boxes,
    }


def _name(folder: Path) -> str:
    name = re.sub(r"[^A-Za-z0-9_.+-]", "_", folder.resolve().name)[:64].strip(".")
    return name or "wokwi"


def _check_board_attrs(diagram) -> None:
    for name in diagram.board_part.attrs:
        if name not in BOARD_ATTRS:
            near = difflib.get_close_matches(name, BOARD_ATTRS, n=1, cutoff=0)
            raise ConfigError(
                f"{diagram.path}: {diagram.board_part.where()}: attrs.{name}: unknown attribute; nearest: {near[0]!r}"
            )


def _check_wokwi_toml(folder: Path) -> None:
    """``wokwi.toml``: Wokwi's own settings (its firmware image, a debugger's port) change
    nothing here; custom chips (``[[chip]]``) are refused, unknown keys named."""
    path = folder / "wokwi.toml"
    if not path.is_file():
        return
    try:
        data = tomllib.loads(path.read_text())
    except (tomllib.TOMLDecodeError, UnicodeDecodeError, OSError) as e:
        raise ConfigError(f"{path}: not TOML: {e}") from None
    except RecursionError:
        raise ConfigError(f"{path}: not TOML: {too_deep(path.read_bytes()) or 'nested too deep'}") from None
    if "chip" in data:
        raise ConfigError(f"{path}: [[chip]]: custom chips are not run here (docs/wokwi.md)")
    for key in data:
        if key not in WOKWI_TABLES:
            near = difflib.get_close_matches(key, sorted(WOKWI_TABLES), n=1, cutoff=0)
            raise ConfigError(f"{path}: [{key}]: unknown table; nearest: [{near[0]}]")
    for key in data.get("wokwi", {}):
        if key not in WOKWI_KEYS:
            near = difflib.get_close_matches(key, sorted(WOKWI_KEYS), n=1, cutoff=0)
            raise ConfigError(f"{path}: [wokwi] {key}: unknown key; nearest: {near[0]!r}")
