"""What a live rig shows at a paused instant, as plain data (``docs/live.md``): the
firmware's pins as the shim configured them, bus transactions, faults checked against the
instant they are given at."""

from host.core.errors import ConfigError
from host.link import frames as F
from host.rig.hardware import peripherals
from host.rig.hardware.bustrace import describe
from host.scenario.runner import pin_level
from sim_plant.faults import HARNESS_KINDS, FaultError, check_against, parse_faults

MODES = {F.PIN_IN: "in", F.PIN_OUT: "out", F.PIN_OPEN_DRAIN: "open_drain", F.PIN_ALT: "alt"}
PULLS = {F.PULL_NONE: None, F.PULL_UP: "up", F.PULL_DOWN: "down"}


def pins(rig) -> dict[str, dict]:
    """Each pin, ADC, PWM and UART the firmware configured, by its board name (or the
    shim's pin id): its ``kind``, ``mode`` and ``pull`` (a pin's), the ``signal`` it is
    wired to, its ``level`` now (an input's as the plant drives it, an output's as the
    firmware last wrote it), a PWM's ``duty_u16`` and ``freq``."""
    out = {}
    for handle in rig.wiring.handles:
        if not handle.kind:
            continue
        name = handle.board_name or handle.key
        row = {"kind": peripherals.name_of(handle.kind), "key": handle.key, "signal": handle.signal}
        if handle.kind == F.CFG_PIN:
            row["mode"], row["pull"] = MODES.get(handle.mode, handle.mode), PULLS.get(handle.pull, handle.pull)
        if handle.kind == F.CFG_PWM:
            row["duty_u16"], row["freq"] = handle.level, handle.freq
        elif handle.kind in (F.CFG_PIN, F.CFG_IRQ):
            row["level"] = pin_level(rig, "", handle.key)[0]
        elif handle.kind == F.CFG_UART:
            row["baud"] = handle.freq
        out[name] = row
    return out


def level(rig, pin: str) -> int:
    """``pin``'s level now: a board pin by its rig name (``LED``), its id (``GP25``, ``25``),
    or a plant signal (``start.out``)."""
    part, _, name = pin.rpartition(".")
    return pin_level(rig, part, name)[0]


def transaction(tx) -> dict:
    """A bus transaction as plain data (``host/rig/hardware/bustrace.py``), with its decoded text."""
    return {
        "t_us": tx.t_us,
        "bus": tx.bus,
        "address": tx.address,
        "register": tx.register,
        "wrote": tx.wrote.hex(),
        "read": tx.read.hex(),
        "status": tx.status,
        "text": describe(tx),
    }


def fault_at(entry: dict, t_us: int, plant) -> dict:
    """A fault entry to inject at ``t_us``: its window starts then unless it says later
    (``start_s``; a brown-out's ``at_s``), checked as a rig file's ``[[faults]]`` are.
    A fault that would act before ``t_us``, or that belongs to the whole run (the link's,
    the heap's), is a ConfigError."""
    entry = dict(entry)
    kind = entry.get("kind")
    now_s = t_us / 1e6
    if kind in HARNESS_KINDS and kind != "brownout":
        raise ConfigError(f"fault {kind!r} acts from the run's start: give it in the rig's faults, not live")
    key = "at_s" if kind == "brownout" else "start_s"
    if kind != "brownout":
        entry.setdefault(key, now_s)
    if entry.get(key, now_s) < now_s:
        raise ConfigError(f"fault {kind!r}: {key} = {entry[key]:g} s is before now (t = {now_s:g} s)")
    try:
        check_against(parse_faults([entry]), plant)
    except FaultError as e:
        raise ConfigError(f"fault to inject: {e}") from e
    return entry
