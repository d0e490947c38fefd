"""The code against the wiring: ``mpy-fil check``'s warnings for a pin the firmware uses that
the rig does not wire, and for a wired pin the firmware never touches, each naming both sides.

The firmware's pins come from :mod:`host.rig.scan.pinscan` (read, not run), its board's from the rig
file; pins are compared as the shim names them (``"18"``, ``"GP14"``, ``"uart2"``).
"""

from dataclasses import dataclass, field

from host.rig.scan.boards import board_names, canonical_key, identity, is_builtin_line, pin_key
from host.rig.scan.pinscan import PinUse, Scan, scan_folder

CLOCK_INPUT = ".sck"
"""An SPI chip's clock input (``<name>.sck``): the pin of its clock, an SPI's ``sck=`` line,
is wired to it rightly (chips sharing one controller's MOSI, a clock pin each: docs/wiring.md)."""


@dataclass
class PinCheck:
    """What ``check`` says of the pins: warnings (one line each), and what it could not tell."""

    warnings: list[str] = field(default_factory=list)
    checked: int = 0  # pins the code uses that were compared
    unchecked: list[str] = field(default_factory=list)  # "main.py:30: Pin(cfg['echo'])"
    notes: list[str] = field(default_factory=list)


def scan_app(app, board: str | None = None) -> Scan:
    """The pins an app's firmware uses on ``board`` (its default): the modules its entry file
    imports, found along the board's path (the app's folder, its libraries, the board file)."""
    board = board or app.default_board
    board_folder = app.board_files(board)[0]
    folders = app.firmware_folders(board_folder)
    platform = (app.board.identity or identity(board) or ("",))[0]
    return scan_folder(folders[0], folders[1:], entry=app.code.entry, family=platform or None)


def check_pins(app, plant=None) -> PinCheck:
    """The app's firmware against its wiring, on its default board (and, given the
    ``plant``, its buses against the devices the plant puts on them)."""
    scan = scan_app(app)
    pins = app.board_files(app.default_board)[1]
    platform, machine = (app.board.identity or identity(app.default_board) or ("", ""))[:2]
    result = compare(scan, pins, app.wiring, platform, board_names(machine))
    if plant is not None:
        result.warnings += compare_buses(scan, plant.bus_names())
        result.warnings += unwired_chip_selects(plant.chip_selects(), app.wiring)
    return result


def unwired_chip_selects(selects: dict, wiring: dict[str, str]) -> list[str]:
    """A part on SPI whose chip select (``selects``: part -> (bus, its cs input)) no pin is
    wired to: it is never selected, so nothing the firmware sends on its bus reaches it."""
    wired = set(wiring.values())
    return [
        f"check: the rig wires no pin to {cs}, the chip select of {name} on {bus}: it is never selected "
        f"(nothing sent on {bus} reaches it); wire the pin the firmware drives as its CS ([wiring] <PIN> = "
        f'"{cs}"), or tie it low with cs = "low" in its [[plant.parts]] table'
        for name, (bus, cs) in sorted(selects.items())
        if cs not in wired
    ]


def compare_buses(scan: Scan, devices: dict[str, list[str]]) -> list[str]:
    """A device on a bus the code never creates (``devices``: bus -> part names), named."""
    if scan.buses_unknown:
        return []  # (a bus made from values only a run can tell may be that one)
    made = ", ".join(sorted(scan.buses)) or "none"
    return [
        f"check: the rig puts {', '.join(names)} on bus {bus}, but the code never creates {bus} "
        f"(the buses it creates: {made}); I2C(n) is i2cn, SPI(n) spin, SoftI2C(scl, sda) i2c:<scl>,<sda>"
        for bus, names in sorted(devices.items())
        if bus not in scan.buses
    ]


def compare(
    scan: Scan, pins: dict, wiring: dict[str, str], platform: str | None = None, names: dict | None = None
) -> PinCheck:
    """``scan``'s pins against a board's ``pins`` (name -> number or name) and the rig's
    ``wiring`` (pin name -> signal); ``names``: the board's own pin names (a kit's board)."""
    result = PinCheck(checked=len(scan.uses), unchecked=list(scan.unchecked), notes=list(scan.notes))
    used: dict = {}
    for key, uses in scan.by_key().items():  # (Pin("GP14") is Pin(14), as the shim sends it)
        used.setdefault(canonical_key(key, platform, names), []).extend(uses)
    wired = {pin_key(name, pins[name]): name for name in wiring if name in pins}
    untouched = {key: name for key, name in wired.items() if key not in used and not is_builtin_line(key)}
    for key, uses in used.items():
        lines = [use for use in uses if use.kind == "bus"]
        if lines and key in wired and wiring[wired[key]].endswith(CLOCK_INPUT):  # (an SPI chip's clock pin)
            lines = [use for use in lines if not use.call.startswith(("SPI(sck=", "SoftSPI(sck="))]
        if lines and key in wired:  # a bus line is no plant signal: both cannot be right
            name = wired[key]
            result.warnings.append(
                f"check: the code makes {lines[0].call} ({lines[0].where}), a bus line, on pin {_shown(key)}, "
                f"but the rig wires {name} = {pins[name]} to the plant's {wiring[name]}"
            )
        uses = [use for use in uses if use.kind != "bus"]
        if not uses or key in wired:
            continue
        use = uses[0]
        text = f"check: the code uses {use.call} ({use.where}{_as(use)}) but the rig wires no pin {_shown(key)}"
        other = _same_name(use, untouched)
        if other is not None:
            name = untouched.pop(other)
            text += f"; the rig wires {name} = {pins[name]} ({wiring[name]}), which the code never touches"
        result.warnings.append(text)
    maybe = " (some pins are computed at run time: check -v lists them)" if scan.unchecked else ""
    maybe = maybe or (" (some files could not be read: check lists them)" if scan.notes else "")
    bases = [(int(k), u) for k, uses in used.items() if k.isdigit() for u in uses if u.kind == "pio"]
    for key, name in untouched.items():
        group = _pio_group(key, bases)
        if group is not None:
            result.notes.append(
                f"check: the rig wires {name} = {pins[name]} ({wiring[name]}), which the code does not name; "
                f"it may be in the PIO pin group from {group.call} ({group.where}): its size is the program's"
            )
            continue
        result.warnings.append(
            f"check: the rig wires {name} = {pins[name]} ({wiring[name]}), but the code never touches pin {_shown(key)}"
            + maybe
        )
    return result


PIO_GROUP_MAX = 32  # a PIO pin group's pins at most (the RP2040's in_count: 32; set: 5; side-set: 5)


def _pio_group(key: str, bases: list) -> PinUse | None:
    """The PIO pin group (its first pin's use, of ``bases``: (pin, use)) that pin ``key``
    may belong to, or None."""
    if not key.isdigit():
        return None
    near = [(int(key) - b, u) for b, u in bases if 0 < int(key) - b < PIO_GROUP_MAX]
    return min(near, key=lambda d: d[0])[1] if near else None


def _as(use: PinUse) -> str:
    return f", as {use.name}" if use.name else ""


def _shown(key: str) -> str:
    return f"UART {key[4:]}" if key.startswith("uart") else key


def _same_name(use: PinUse, untouched: dict[str, str]) -> str | None:
    """The untouched wired pin the code's name for ``use`` names (ECHO, board.ECHO, sonar.echo)."""
    if not use.name:
        return None
    names = {use.name.upper(), use.name.split(".")[-1].upper(), use.name.replace(".", "_").upper()}
    return next((key for key, name in untouched.items() if name.upper() in names), None)
