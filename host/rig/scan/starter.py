"""``mpy-fil init``: a commented starting rig file for a firmware folder.

The pins come from :mod:`host.rig.scan.pinscan`, each named after the code's own name for it
(``ENA``, ``IN1``, ``TRIG``; ``PIN_7`` for a bare ``Pin(7)``). When the names and the pins'
use show the motors' H-bridge (TB6612: IN1/IN2/PWM per motor and STBY; L298N: ENA/IN1/IN2,
ENB/IN3/IN4; DRV8833: two PWM per motor; DIR+PWM), the file describes the robot as a body and
parts (``[plant] body = "differential"``, a ``dc_motor`` part per motor and an ``hcsr04`` per
TRIG/ECHO pair, wired); otherwise it
starts from a usual two-wheel robot's parts (TB6612 motors, encoders, an HC-SR04), unwired.
"""

import re
from dataclasses import dataclass
from pathlib import Path

from host.rig.scan.pinscan import PinUse, firmware_sources, scan_folder

DEFAULT_FORM = """\
[plant]                    # a body and its parts: docs/parts.md, mpy-fil list
body = "differential"      # or "bench": a breadboard, no body

[[plant.parts]]
kind = "dc_motor"          # signals motor_l.in1, motor_l.in2, motor_l.pwm
name = "motor_l"
bridge = "tb6612"          # tb6612 | l298n | drv8833 | dir_pwm
drives = "left"

[[plant.parts]]
kind = "dc_motor"
name = "motor_r"
bridge = "tb6612"
drives = "right"

[[plant.parts]]
kind = "encoder"           # enc_l.a, enc_l.b (channels = "single": enc_l.out)
name = "enc_l"
wheel = "left"

[[plant.parts]]
kind = "encoder"
name = "enc_r"
wheel = "right"

[[plant.parts]]
kind = "hcsr04"            # sonar.trig, sonar.echo
name = "sonar"
mount = {{ x_m = 0.08, y_m = 0.0, heading_deg = 0 }}

# [[plant.parts]]
# kind = "button"          # start.out
# name = "start"
# presses = [[1.0, 1.2]]   # pressed at s, released at s
"""
BODY_FORM = """\
[plant]                    # the robot as a body and parts (docs/parts.md lists them)
body = "differential"
# wheel_radius_m = 0.0325
# track_m = 0.15
{parts}
# [[plant.parts]]          # more parts: encoder, hcsr04, bumper, button, line_sensor, ...
# kind = "hcsr04"
# name = "sonar"
"""
STARTER = """\
# The test rig of {name}: this folder's firmware on a simulated robot (docs/rig-file.md).
# Check it with `mpy-fil check {path}`; run it with `mpy-fil run {path}`.
name = "{name}"

[firmware]
entry = "{entry}"          # what runs after boot.py
# lib = ["lib"]            # library folders of your own
# harness_lib = false      # the harness's own drivers (firmware/lib): off unless you ask

{board}[board.pins]               # the pins your code uses, by the code's own names
{pins}
{plant}
[wiring]                   # pin name = plant signal (mpy-fil check lists them), or probe:<name>
{wiring}
# [budgets.loop]           # a timing budget: a pin toggled once per loop, every 50 ms
# kind = "period"
# source = "probe:loop"
# period_us = 50_000
# tolerance_us = 1_000
"""
RP2_BOARD = """\
[board]
family = "rpi_pico"        # the code names rp2 (import rp2, "GP14"): an RP2040; "rpi_pico2" for an RP2350

"""
ROLE_NAMES = {"IN1": "in1", "IN2": "in2", "PWM": "pwm", "EN": "pwm", "SPEED": "pwm", "DIR": "dir", "PHASE": "dir"}


@dataclass(frozen=True)
class _Pin:
    name: str  # the board pin's name in the rig file
    value: int | str
    use: PinUse


def starter(folder: Path, notes: list | None = None) -> str:
    """A commented starting rig file for a firmware folder: its entry file, the pins its code
    uses by the code's names, and the motors' bridge when the pins show it; what it skipped or
    where it stopped early goes to ``notes``."""
    files = sorted(folder.glob("*.py"))
    entry = "main.py" if (folder / "main.py").is_file() or not files else files[0].name
    family = _family(folder)
    scan = scan_folder(folder, family=family)
    if notes is not None:
        notes.extend(scan.notes)
    pins = _named(scan.uses)
    motors = guess_motors(pins)
    wired = {pin.name: f"{motor}.{signal}" for motor, (_, roles) in motors.items() for signal, pin in roles.items()}
    if motors and any(pin.name == "STBY" for pin in pins):
        wired["STBY"] = "probe:stby"  # the TB6612's standby: high to run (a probe shows it)
    rangers = guess_rangers(pins) if motors else {}
    for ranger, (trig, echo) in rangers.items():
        wired |= {trig.name: f"{ranger}.trig", echo.name: f"{ranger}.echo"}
    lines = "".join(f"{pin.name} = {_toml(pin.value)}\n" for pin in pins)
    wiring = "".join(
        f'{pin.name} = "{wired[pin.name]}"\n' if pin.name in wired else f'# {pin.name} = "..."\n' for pin in pins
    )
    return STARTER.format(
        name=folder.resolve().name,
        path=folder / "rig.toml",
        entry=entry,
        board=RP2_BOARD if family == "rp2" else "",
        pins=lines or "# LED = 25\n",
        plant=BODY_FORM.format(parts=_parts(motors) + _ranger_parts(rangers)) if motors else DEFAULT_FORM.format(),
        wiring=wiring or '# LED = "probe:led"\n',
    )


def _family(folder: Path) -> str | None:
    """``rp2`` when the code names the RP2040 (``import rp2``, ``"GP14"``): its ``ADC(0)`` is GP26."""
    for path in firmware_sources(folder):
        try:
            text = path.read_text(errors="replace")
        except OSError:
            continue
        if re.search(r"\bimport rp2\b|[\"']GP\d+[\"']|\brp2\b", text):
            return "rp2"
    return None


def _named(uses: list[PinUse]) -> list[_Pin]:
    """One board pin a pin the code uses, named as the code names it (first use wins), in pin order."""
    by_key: dict[str, _Pin] = {}
    taken: set[str] = set()
    for use in uses:
        if use.key in by_key:
            continue
        value: int | str = int(use.key[4:] if use.kind == "uart" else use.key) if _is_int(use) else use.key
        base = re.sub(r"\W+", "_", (use.name or "").replace("[", "_").replace("]", "")).strip("_").upper()
        base = base if base and not base[0].isdigit() else f"PIN_{value}"
        if use.kind == "uart" and not base.endswith("_UART"):
            base += "_UART"  # (a board constant ending in _UART names a UART id)
        name, n = base, 2
        while name in taken:
            name, n = f"{base}_{n}", n + 1
        taken.add(name)
        by_key[use.key] = _Pin(name, value, use)
    return sorted(by_key.values(), key=lambda p: (isinstance(p.value, str), p.value if isinstance(p.value, int) else 0))


def _is_int(use: PinUse) -> bool:
    return (use.key[4:] if use.kind == "uart" else use.key).lstrip("-").isdigit()


def _toml(value) -> str:
    return str(value) if isinstance(value, int) else f'"{value}"'


def guess_motors(pins: list[_Pin]) -> dict[str, tuple[str, dict[str, _Pin]]]:
    """The motors the pins show: ``motor_l``/``motor_r`` -> (bridge, signal -> pin), or {}."""
    groups: dict[str, dict[str, _Pin]] = {}
    hints: set[str] = set()
    for pin in pins:
        found = _role(pin.name)
        if found:
            group, role, hint = found
            groups.setdefault(group, {}).setdefault(role, pin)
            hints |= {hint} if hint else set()
    motors = {}
    for group, roles in groups.items():
        bridge = _bridge(roles, hints)
        if bridge:
            signals = {
                "in1": roles.get("in1"),
                "in2": roles.get("in2"),
                "pwm": roles.get("pwm"),
                "dir": roles.get("dir"),
            }
            motors[group] = (bridge, {s: p for s, p in signals.items() if p is not None})
    if not 1 <= len(motors) <= 2:
        return {}
    ordered = sorted(motors, key=lambda g: (not re.search(r"(^|_)(L|LEFT|A|1)($|_)", g), g))
    return {f"motor_{side}": motors[g] for side, g in zip("lr", ordered)}


def _role(name: str) -> tuple[str, str, str | None] | None:
    """(motor group, role: in1 in2 pwm dir, bridge hint) of a pin's name, or None."""
    if m := re.fullmatch(r"IN([1-4])", name):  # an L298N's: IN1/IN2 the first motor, IN3/IN4 the second
        return ("A" if int(m[1]) <= 2 else "B"), f"in{2 - int(m[1]) % 2}", "l298n"
    if m := re.fullmatch(r"EN([AB])", name):
        return m[1], "pwm", "l298n"
    if m := re.fullmatch(r"([AB])IN([12])", name):  # a TB6612's AIN1, BIN2, PWMA
        return m[1], f"in{m[2]}", "tb6612"
    if m := re.fullmatch(r"PWM([AB])", name):
        return m[1], "pwm", "tb6612"
    if m := re.fullmatch(r"(.+?)_?(IN[12]|PWM|EN|DIR|PHASE|SPEED)", name):  # MOTOR_L_IN1, LEFT_PWM
        return m[1], ROLE_NAMES[m[2]], None
    if m := re.fullmatch(r"(IN[12]|PWM|EN|DIR)_(.+)", name):  # PWM_L, DIR_R
        return m[2], ROLE_NAMES[m[1]], None
    return None


def _bridge(roles: dict[str, _Pin], hints: set[str]) -> str | None:
    pwm_kind = {role for role, pin in roles.items() if pin.use.kind == "pwm"}
    if {"in1", "in2"} <= set(roles) and {"in1", "in2"} <= pwm_kind and "pwm" not in roles:
        return "drv8833"
    if {"in1", "in2", "pwm"} <= set(roles):
        return "l298n" if hints == {"l298n"} else "tb6612"
    if {"dir", "pwm"} <= set(roles):
        return "dir_pwm"
    return None


def guess_rangers(pins: list[_Pin]) -> dict[str, tuple[_Pin, _Pin]]:
    """HC-SR04s the pins show: a TRIG and an ECHO pin whose names differ only there
    (``TRIG``/``ECHO``, ``TRIG_F``/``ECHO_F``): ``sonar``, ``sonar_f`` -> (trig, echo)."""
    trigs = {re.sub(r"TRIG(GER)?", "#", p.name, count=1): p for p in pins if re.search(r"TRIG", p.name)}
    echos = {re.sub(r"ECHO", "#", p.name, count=1): p for p in pins if "ECHO" in p.name}
    found = {}
    for key in sorted(trigs.keys() & echos.keys()):
        rest = re.sub(r"_?PIN\b|#", "", key).strip("_").lower()
        found[f"sonar_{rest}" if rest else "sonar"] = (trigs[key], echos[key])
    return found


def _ranger_parts(rangers: dict) -> str:
    return "".join(f'\n[[plant.parts]]\nkind = "hcsr04"\nname = "{name}"\n' for name in rangers)


def _parts(motors: dict) -> str:
    side = {"motor_l": "left", "motor_r": "right"}
    return "".join(
        f'\n[[plant.parts]]\nkind = "dc_motor"\nname = "{name}"\nbridge = "{bridge}"\ndrives = "{side[name]}"\n'
        for name, (bridge, _) in motors.items()
    )
