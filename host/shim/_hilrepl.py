# The firmware looked at while it waits (docs/live.md, "Looking inside the firmware").
# The host holds the clock while the firmware waits for a STATE; an EVAL that comes then
# (_hil's _Link.exchange) is answered here before the wait goes on: an expression read in
# the firmware's globals (the entry file's, as a board's REPL has them) and its loaded
# modules, or a REPL line run in those globals. Virtual time does not move: the line runs
# as a handler does at its instant (its clock reads move no time), its compute is not the
# board's (MCU time), and the link is closed to it (an output, a wait, a bus transfer
# raises), so it can read and set Python state but not drive the board. Imported on the
# first EVAL only: a run that makes none never loads it.
import sys

import _hil
import _hilframe as F


class NotAtAPause(Exception):
    pass


def _refuse(type_, payload):
    raise NotAtAPause(
        "the firmware is paused: a line run by the host cannot drive the board or wait (it tried to send %s)"
        % F.NAMES.get(type_, type_)
    )


def _globals():
    import __main__

    return __main__.__dict__


def _error(e):
    import io

    out = io.StringIO()
    sys.print_exception(e, out)
    return out.getvalue()


# The line's code is named as a file of the shim's folder: with MCU time its work is the
# harness's, not the board's compute (_hilfast.exempt counts by a function's source file).
_NAME = __file__.rsplit("/", 1)[0] + "/<live>"


def _run(mode, source):
    env = _globals()
    if mode == F.EVAL_EXPR:
        scope = {}
        for name in sys.modules:  # a module's attribute (motor.duty) as well as a global's
            if "." not in name:
                scope[name] = sys.modules[name]
        for name in env:
            scope[name] = env[name]
        return F.EVAL_VALUE, repr(eval(compile(source, _NAME, "eval"), scope))
    try:
        code = compile(source, _NAME, "eval")
    except SyntaxError:
        exec(compile(source, _NAME, "exec"), env)
        return F.EVAL_NONE, ""
    value = eval(code, env)
    return (F.EVAL_NONE, "") if value is None else (F.EVAL_VALUE, repr(value))


def answer(link, p):
    """The EVAL ``p``'s EVAL_REPLY, sent on ``link`` (nothing else leaves while it runs)."""
    mode, source = F.unpack_eval(p)
    queue = link.queue
    link.queue = _refuse
    dispatching, reads = _hil._dispatching, _hil._cb_reads
    _hil._dispatching = True  # (its clock reads move no time, as a hard handler's at its instant)
    _hil._cb_reads = _hil._HELD
    try:
        status, text = _run(mode, source.decode())
    except BaseException as e:  # (sys.exit or machine.reset in a line: said, not done)
        status, text = F.EVAL_ERROR, _error(e)
    finally:
        _hil._dispatching, _hil._cb_reads = dispatching, reads
        link.queue = queue
    queue(F.EVAL_REPLY, F.pack_eval_reply(status, text.encode()))
    link.flush()
