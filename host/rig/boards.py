"""Board pin maps: ``firmware/boards/<board>/board.py`` is the one place pin numbers
live. The host reads it without running it (it is MicroPython: ``const()``)."""

import ast
from pathlib import Path

from host.core.errors import ConfigError
from host.core.paths import BOARDS_DIR

# What a board's firmware sees as sys.platform and sys.implementation._machine, by the
# family its name starts with; a board of no known family keeps the unix port's own.
IDENTITIES = {
    "esp32": ("esp32", "Generic ESP32 module with ESP32"),
    "rpi_pico": ("rp2", "Raspberry Pi Pico with RP2040"),
}


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
    """Constant name -> value (pin number or name) from a named board's file."""
    return read_board_file(board_dir(board) / "board.py")


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
    return f"uart{value}" if name.endswith("_UART") else str(value)
