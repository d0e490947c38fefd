"""Board pin maps: ``firmware/boards/<board>/board.py`` is the one place pin numbers
live. The host reads it without running it (it is MicroPython: ``const()``)."""

import ast
from pathlib import Path

from host.core.errors import ConfigError
from host.core.paths import BOARDS_DIR

# What a board's firmware sees as sys.platform and sys.implementation._machine, by the
# family its name starts with; a board of no known family keeps the unix port's own.
# (The first family whose name begins the board's: rpi_pico2 before rpi_pico.)
IDENTITIES = {
    "esp32": ("esp32", "Generic ESP32 module with ESP32"),
    "rpi_pico2": ("rp2", "Raspberry Pi Pico2 with RP2350"),
    "rpi_pico": ("rp2", "Raspberry Pi Pico with RP2040"),
    # kits' boards: MICROPY_HW_BOARD_NAME of ports/rp2/boards/<BOARD>/mpconfigboard.h, " with ",
    # the chip (their pin names: host/shim/_hilboards.py), or the name alone where the board
    # sets MICROPY_BANNER_MACHINE to it (its chip then in host/rig/targets/mcutime.py BANNER_CHIPS)
    "sparkfun_xrp_controller_beta": ("rp2", "SparkFun XRP Controller (Beta) with RP2040"),
    "sparkfun_xrp_controller": ("rp2", "SparkFun XRP Controller with RP2350"),
    "pololu_3pi_2040_robot": ("rp2", "Pololu 3pi+ 2040 Robot"),
}


# Lines of a family's board that are no GPIO, wired by name in a rig file's [wiring] with no
# [board.pins] entry: rp2's BOOTSEL button (on QSPI_SS; rp2.bootsel_button() reads it,
# ports/rp2/modrp2.c) and its temperature sensor (ADC(4), ADC.CORE_TEMP: ports/rp2/
# machine_adc.c). The shim names its handle so.
BUILTIN_LINES = {"rp2": {"BOOTSEL": "BOOTSEL", "CORE_TEMP": "CORE_TEMP"}}


def with_builtin_lines(pins: dict, platform: str | None) -> dict:
    """A board's pins and its family's built-in lines (a pin of the board's own name wins)."""
    return {**BUILTIN_LINES.get(platform or "", {}), **pins}


def is_builtin_line(key: str) -> bool:
    return any(key in lines for lines in BUILTIN_LINES.values())


def identity(board: str | None) -> tuple[str, str] | None:
    """(sys.platform, sys.implementation._machine) for a board, or None."""
    for family, ident in IDENTITIES.items():
        if board and board.startswith(family):
            return ident
    return None


def known_boards() -> list[str]:
    """Our boards: the folders of firmware/boards that hold a board.py."""
    return sorted(p.name for p in BOARDS_DIR.iterdir() if (p / "board.py").is_file())


def board_dir(board: str) -> Path:
    path = BOARDS_DIR / board / "board.py"
    if not path.is_file():
        raise ConfigError(f"board: no pin map {path} (known boards: {', '.join(known_boards())})")
    return path.parent


def read_pin_map(board: str) -> dict[str, object]:
    """Constant name -> value (pin number or name) from a named board's file, with its
    family's built-in lines (BUILTIN_LINES)."""
    return with_builtin_lines(read_board_file(board_dir(board) / "board.py"), (identity(board) or (None,))[0])


def read_board_file(path: Path) -> dict[str, object]:
    """Constant name -> value (pin number or name) from a board file; a file that is
    not Python raises ConfigError naming its line."""
    if not path.is_file():
        raise ConfigError(f"no board file {path}")
    try:
        tree = ast.parse(path.read_text(), str(path))
    except SyntaxError as e:
        raise ConfigError(f"{path}:{e.lineno}: SyntaxError: {e.msg}") from None
    names: dict[str, object] = {}
    for node in tree.body:
        if isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Name):
            value = node.value
            if isinstance(value, ast.Call) and getattr(value.func, "id", "") == "const" and value.args:
                value = value.args[0]
            if isinstance(value, ast.Constant):
                names[node.targets[0].id] = value.value
    return names


def pin_key(name: str, value: object) -> str:
    """How the shim names a resource: the pin id as text, or ``uart<id>`` for UARTs
    (board constants whose name ends in ``_UART``)."""
    return f"uart{value}" if name.endswith("_UART") else canonical_key(str(value))


def board_names(machine: str | None) -> dict[str, int]:
    """A kit board's pin names (its pins.csv) by its ``sys.implementation._machine``, as the
    shim has them (host/shim/_hilboards.py, read here as data); {} for any other board."""
    if not machine or machine.startswith("Raspberry Pi Pico"):
        return {}
    from host.core.paths import SHIM_DIR

    space: dict = {}
    exec(compile((SHIM_DIR / "_hilboards.py").read_text(), "_hilboards.py", "exec"), space)  # (our own table)
    found = space["board"](machine)
    return dict(found[1]) if found else {}


def canonical_key(key: str, platform: str | None = None, names: dict | None = None) -> str:
    """An rp2 GPIO's name as the shim sends it: ``"GP14"`` and ``"GPIO14"`` are pin 14
    (ports/rp2/machine_pin.c, machine_pin_find: Pin("GP14") is Pin(14)); on an rp2,
    ``"LED"`` is the Pico's GP25 (boards/RPI_PICO/pins.csv); ``names``: a kit board's own
    (:func:`board_names`), ``"MOTOR_L_IN_1"`` on an XRP."""
    if names and key in names:
        return str(names[key])
    if platform == "rp2" and key == "LED":
        return "25"
    for prefix in ("GPIO", "GP"):
        if key.startswith(prefix) and key[len(prefix) :].isdigit():
            return str(int(key[len(prefix) :]))
    return key
