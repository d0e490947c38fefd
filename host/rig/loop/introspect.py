"""The firmware looked at while it is paused (``docs/live.md``, "Looking inside the
firmware"): the host holds the clock while the firmware waits for a STATE, so an EVAL sent
then is answered (``host/shim/_hilrepl.py``) before the wait goes on, and virtual time does
not move. An expression is read in the firmware's globals and its loaded modules; a REPL
line runs in its globals. Neither may drive the board or wait: the shim refuses any frame
the line would send, and the line's error comes back as :class:`FirmwareEvalError`."""

from host.core.errors import HarnessError, LinkError
from host.core.printable import printable
from host.link import frames as F

EVAL_TIMEOUT_S = 10.0
"""Wall seconds an EVAL may take before the firmware is taken for hung."""


class FirmwareEvalError(HarnessError):
    """What the host ran in the paused firmware raised there: the message is its traceback."""


def firmware_eval(rig, source: str, line: bool = False) -> tuple[int, str]:
    """``(status, text)``: ``F.EVAL_VALUE`` and the value's repr, or ``F.EVAL_NONE``
    (a statement, or None); ``source`` an expression, or with ``line`` a REPL line. The
    firmware must be paused in a wait (after a ``run_until``)."""
    if rig.exit_kind is not None or not rig.target.alive():
        raise LinkError(f"cannot look inside the firmware: it is not running{rig.where()}")
    if rig.clock.wait is None:
        raise LinkError("cannot look inside the firmware: it is not paused in a wait (run the rig to an instant first)")
    rig.session.send(F.EVAL, F.pack_eval(F.EVAL_LINE if line else F.EVAL_EXPR, source.encode()))
    what = "EVAL_REPLY (a shim older than the EVAL message ignores it)"
    type_, payload = rig.session.recv(EVAL_TIMEOUT_S, what)
    if type_ != F.EVAL_REPLY:
        raise LinkError(f"expected EVAL_REPLY from the shim, got {F.NAMES.get(type_, hex(type_))}{rig.where()}")
    status, text = F.unpack_eval_reply(payload)
    text = text.decode(errors="replace")
    if status == F.EVAL_ERROR:
        kind = "the line" if line else "the expression"
        raise FirmwareEvalError(
            printable(
                f"{kind} {source!r}, run in the firmware paused at virtual t={rig.clock.wait.t_now / 1e6:.6f} s, "
                f"raised there:\n{text.rstrip()}"
            )
            + rig.where()
        )
    return status, text
