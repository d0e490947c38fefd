"""How a firmware run ends, and the errors that say so. Each stops the rig first and
names the virtual time, the seed, the console's last lines and the artefacts
(``Rig.where``): a traceback, an exit the test did not expect, a boot loop, a damaged
link. ``docs/reliability.md`` lists them with the tests that show them."""

from host.core.errors import FirmwareError, FirmwareExited, FirmwareHung, LinkDamaged, LinkError
from host.link import frames as F

BOOT_LOOP_RESETS = 20
BOOT_LOOP_US = 1_000
"""BOOT_LOOP_RESETS resets within BOOT_LOOP_US of virtual time: a boot loop."""
SHIM_LINK_DAMAGED = "LinkDamaged:"  # the shim's exception, last line of its traceback
CONSOLE_TAIL_LINES = 20


def where(rig) -> str:
    """The console's last lines, the seed and the artefacts folder, for error messages."""
    tail = "\n".join(rig.console.rstrip().splitlines()[-CONSOLE_TAIL_LINES:])
    console = f"\nconsole (last {CONSOLE_TAIL_LINES} lines):\n{tail}" if tail else "\nconsole: (empty)"
    return console + f"\nseed: {rig.seed}" + (f"\nartefacts: {rig.artefacts}" if rig.artefacts else "")


def fault(rig, t: int, text: str):
    """The firmware raised (FAULT): its traceback, whole, ends the run."""
    try:
        rig.session.recv(1.0, "EXIT")  # let the process finish writing
    except (LinkError, FirmwareError, FirmwareHung):
        pass
    rig.stop()
    last = text.rstrip().splitlines()[-1] if text.strip() else ""
    if last.startswith(SHIM_LINK_DAMAGED):
        raise LinkDamaged(
            f"{last[len(SHIM_LINK_DAMAGED) :].strip()} (seen by the shim at virtual t={t / 1e6:.6f} s){rig.where()}"
        )
    raise FirmwareError(
        f"firmware raised at virtual t={t / 1e6:.6f} s; expected it to keep running.\n"
        f"MicroPython traceback:\n{text.rstrip()}{rig.app.import_hint(text)}{rig.where()}",
        traceback=text,
        console=rig.console,
    )


def exited(rig, t: int, kind: int, code: int) -> None:
    """The entry file returned or called sys.exit: a failure unless the rig expects it."""
    if rig.allow_exit:
        return
    how = "its entry file returned" if kind == F.EXIT_RETURN else f"it called sys.exit({code})"
    rig.stop()
    raise FirmwareExited(
        f"the firmware ended at virtual t={t / 1e6:.6f} s ({how}, exit code {code}); expected it to keep "
        f"running (a test that expects the end makes its rig with allow_exit=True).{rig.where()}",
        code=code,
        console=rig.console,
    )


def reset(rig, t: int) -> None:
    """machine.reset() (or a watchdog): stop a board that does nothing but reset."""
    run = rig.reset_times  # the last BOOT_LOOP_RESETS resets' times
    run.append(t)
    if len(run) == BOOT_LOOP_RESETS and run[-1] - run[0] <= BOOT_LOOP_US:
        rig.stop()
        raise FirmwareError(
            f"boot loop: the firmware reset {BOOT_LOOP_RESETS} times within {BOOT_LOOP_US / 1000:g} ms of "
            f"virtual time (from t={run[0] / 1e6:.6f} s), never getting further; expected it to run."
            f"{rig.where()}",
            console=rig.console,
        )


def damaged(rig, error: LinkDamaged):
    """A frame from the firmware was damaged or lost: nothing after it can be trusted."""
    rig.stop()
    raise LinkDamaged(f"{error} (at virtual t={rig.clock.firmware_us / 1e6:.6f} s){rig.where()}") from None
