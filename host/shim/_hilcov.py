# Firmware coverage (docs/coverage.md): a sys.settrace tracer, on the interpreter variant
# built with MICROPY_PY_SYS_SETTRACE, that records the arcs (and so the lines) the
# firmware's own files run: not the shim's (/_hil, or the shim's folder unconfined) nor
# the frozen modules (no file on the flash: asyncio/core.py). Started by _hilboot before boot.py when the host passes
# HIL_COVERAGE_FD (a file it opened for appending); saved there before the shim tells the
# host the firmware ended, one block per boot:
#   F <filename>
#   A <from>,<to> <from>,<to> ...   (from < 0: entry into a code object; to < 0: its exit)
# It changes nothing the firmware or the host sees but wall time and the heap (the
# closures and frame objects it costs are garbage at once); under heap_lock it records
# what it can without allocating.
import os
import sys

_OFFSET = 1 << 20  # an arc packed into one small int: (from + _OFFSET) << 21 | to


def _arcs_of(filename):
    """The arcs recorded of ``filename`` (a set), None for a file not traced (start sets it)."""


def save():
    """Write what was recorded (once: tracing stops); nothing before start()."""


def start(fd, skip):
    """Trace from here on; ``fd``: the host's file; ``skip``: filename prefixes not traced."""
    global _arcs_of, save
    if not hasattr(sys, "settrace"):
        raise OSError("coverage needs the interpreter built with MICROPY_PY_SYS_SETTRACE")
    files = {}  # co_filename -> set of packed arcs, or None for a file not traced
    _arcs_of = _arcs_in(files, tuple(skip))
    save = _saver(open(int(fd), "a"), files)
    sys.settrace(_call)


# The host's file, the filenames seen (the shim's files by their host path, loaded before
# the board's flash was mounted) and the prefixes skipped (the shim's folder on the host)
# are held only in the closures below (MicroPython has no __closure__), never in a global:
# the firmware, which can reach this module, gets no handle to write the harness's
# coverage data and no host path (docs/security.md, "The link and the coverage file").
def _arcs_in(files, skip):
    def arcs_of(filename):
        arcs = files.get(filename, 0)
        if arcs == 0:
            arcs = None
            if not filename.startswith(skip) and _on_flash(filename):
                arcs = set()
            files[filename] = arcs
        return arcs

    return arcs_of


def _on_flash(filename):
    """A file the firmware has (a frozen module, a string's code: none)."""
    try:
        os.stat(filename)
        return True
    except OSError:
        return False


def _call(frame, event, arg):
    try:
        code = frame.f_code
        arcs = _arcs_of(code.co_filename)
        if arcs is None:
            return None
        if frame.f_lasti:  # a generator resumed at its yield
            return _local(arcs, frame.f_lineno, True, _first(code, frame))
        first = _first(code, frame)
        return _local(arcs, -first, False, first)
    except MemoryError:  # (under heap_lock: this frame goes untraced)
        return None


def _first(code, frame):
    return 1 if code.co_name == "<module>" else frame.f_lineno


def _local(arcs, last, resumed, first):
    state = [last, resumed]

    def trace(frame, event, arg):
        try:
            if event == "line":
                line = frame.f_lineno
                if state[1]:  # (the VM repeats the yield's line on resuming)
                    state[1] = False
                    if line == state[0]:
                        return trace
                arcs.add(((state[0] + _OFFSET) << 21) | (line + _OFFSET))
                state[0] = line
            elif event == "return":
                arcs.add(((state[0] + _OFFSET) << 21) | (_OFFSET - first))
        except MemoryError:
            pass
        return trace

    return trace


def _saver(out, files):
    held = [out]

    def save():
        """Write what was recorded (once: tracing stops)."""
        if not held:
            return
        sys.settrace(None)
        out = held.pop()
        for filename, arcs in files.items():
            if arcs:
                out.write("F %s\nA" % filename)
                for packed in arcs:
                    out.write(" %d,%d" % ((packed >> 21) - _OFFSET, (packed & ((1 << 21) - 1)) - _OFFSET))
                out.write("\n")
        out.close()

    return save
