# A poll that never ends, named (docs/reliability.md, "A poll that never ends"): the rare path
# of machine.Pin.value() and machine.mem8/16/32 reads. Both count, per pin and per address,
# the reads in a row that gave one answer (a compare and a decrement a read: the hot path
# stays in machine.py); every POLL_READS of them they call look() here, which names the
# poll once POLL_SPAN_US of virtual time has passed since its first read: a POLL frame to
# the host, which says what would change it (the part that drives the pin per the rig's
# wiring, or that nothing does) in the run's output. Imported at the first look only.
import sys

import _hil
import _hilframe as F

LOOK = 1000  # after the first look, another every LOOK reads (a note at most that late)
_named = set()  # (kind, target) named already: once each


def firmware_stack():
    """The firmware's call stack at this read, outermost first, as lines of text; None
    when the interpreter gives none. MicroPython has no way to walk the caller's frames
    from Python (no sys._getframe, no traceback.extract_stack); the harness's build keeps
    a stack of the running functions (host/core/micropython/hilcount.patch), which
    ``_hilfast.stack`` reads. The shim's own frames are left out."""
    try:
        from _hilfast import stack
    except ImportError:  # (a user's own interpreter)
        return None
    frames = stack(True)
    # the shim's folder as its modules were compiled: before the sandbox (the boot's, under
    # the stdin stub at the bottom) and after it (this function's own, and its __file__)
    shim = {frames[i][0].rsplit("/", 1)[0] for i in (1, -1) if len(frames) > 1}
    shim.add(__file__.rsplit("/", 1)[0])
    return [
        '  File "%s", line %d, in %s' % (f, line, fn)
        for f, fn, line in frames
        if f != "<stdin>" and f.rsplit("/", 1)[0] not in shim
    ] or None


def look(obj, addr, run, register):
    """POLL_READS (then LOOK) more reads with one answer: name the poll once its span is met."""
    if run is None:
        _look_pin(obj)
    else:
        _look_mem(obj, addr, run, register)


def _look_pin(pin):
    pin._pr += LOOK if pin._pr else F.POLL_READS
    if _hil.now() - pin._pt < F.POLL_SPAN_US or (F.POLL_PIN, pin._handle) in _named:
        pin._pn = LOOK
        return
    pin._pn = -1  # (named: its count never comes back to 0 while the answer holds)
    _name(F.POLL_PIN, 1, pin._handle, pin._pv, pin._pt, pin._pr, "")


def _look_mem(mem, addr, run, register):
    run[2] += LOOK if run[2] else F.POLL_READS
    kind = F.POLL_REG if register else F.POLL_MEM
    if _hil.now() - run[3] < F.POLL_SPAN_US or (kind, addr) in _named:
        run[1] = LOOK
        return
    run[1] = -1
    machine = sys.modules["machine"]
    reg = machine._REG
    if reg is not None:
        word = reg.register_text(addr) if register else reg.UNMODELLED
    else:
        word = "no register of the simulated %s is modelled: machine.mem%d is plain memory" % (_board(), mem._bits)
    _name(kind, mem._bits, addr, run[0], run[3], run[2], word)


def _board():
    impl = getattr(sys.modules.get("sys", sys), "implementation", None)
    return getattr(impl, "_machine", "") or "board"


def send_stack(t):
    """The firmware's stack for the poll of a bus register the host names (a BUS_REPLY
    with BUS_ASK_STACK): a POLL of kind POLL_STACK, its text's lines after the first."""
    stack = firmware_stack()
    text = "\n" + "\n".join(stack) if stack else ""
    _hil.send(F.POLL, F.pack_poll(t, t, 0, F.POLL_STACK, 0, 0, 0, text.encode()))


def _name(kind, bits, target, value, since_us, reads, word):
    _named.add((kind, target))
    stack = firmware_stack()
    text = word + ("\n" + "\n".join(stack) if stack else "")
    _hil.send(F.POLL, F.pack_poll(_hil.now(), since_us, reads, kind, bits, target, value & 0xFFFFFFFF, text.encode()))
    _hil._link.flush()  # (now: what the firmware prints after it comes after it, stamped later)
