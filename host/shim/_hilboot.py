# Entry point of a firmware run: `micropython -c "import _hilboot; _hilboot.main()"` on
# the unix port (so __main__ is free for the firmware's entry file), or
# `import _hilboot; _hilboot.main(pil=True)` at a board's REPL (processor in the loop).
# Shakes hands with the host, makes asyncio keep its task queue in virtual time, then
# runs boot.py and main.py from the firmware's folder as a board does, in the same globals
# (on a board, boot.py already ran at power-on), reporting how the firmware ended.
import io
import micropython as _micropython
import sys

import _hil
import _hilframe as F


def _asyncio_in_virtual_time():
    # The C helper _asyncio stamps tasks with the process's own clock and compares
    # ticks with the unix port's period; the pure-Python queue uses time.ticks_ms.
    import asyncio
    import asyncio.core as core

    try:
        import asyncio.task as task
    except ImportError:
        task = None  # (raised below: MicroPython warns at run time on exception chaining)
    if task is None:
        raise ImportError(
            "this MicroPython has no frozen asyncio/task.py; build it with "
            "host/core/micropython/manifest.py (make setup) or freeze that file"
        )

    core.TaskQueue = task.TaskQueue
    core.Task = task.Task
    core._task_queue = task.TaskQueue()
    asyncio.Task = task.Task
    # A task that dies with nobody awaiting it is reported as on a board, then ends the
    # run (a board would carry on without it); a firmware's own handler replaces this.
    default = asyncio.Loop.default_exception_handler

    def task_died(loop, context):
        default(loop, context)
        raise context["exception"]

    asyncio.Loop.default_exception_handler = task_died


def _find(name):
    for folder in sys.path:
        if folder != ".frozen":
            path = folder + "/" + name if folder else name
            try:
                with open(path) as f:
                    return path, f.read()
            except OSError:
                pass
    return None, None


def _fresh_main():
    """The __main__ module as a board's at power-on: empty (here it held the -c command's names)."""
    import __main__

    env = __main__.__dict__
    env.clear()
    env["__name__"] = "__main__"


def _port_boot():
    """The names the port's frozen _boot.py leaves in __main__ before boot.py and main.py run
    there: machine and rp2 on an rp2 (ports/rp2/modules/_boot.py imports them and deletes
    only vfs, bdev and fs), gc and vfs on an ESP32 (ports/esp32/modules/_boot.py deletes
    nothing; its bdev, the flash partition, is not modelled). A main.py that uses
    machine.Pin without importing machine runs on those boards, and so here."""
    import __main__

    env = __main__.__dict__
    platform = sys.modules.get("sys", sys).platform  # (the board's sys: _hilsys)
    if platform == "rp2":
        import machine
        import rp2

        env["machine"] = machine
        env["rp2"] = rp2
    elif platform == "esp32":
        import gc

        import vfs

        env["gc"] = gc
        env["vfs"] = vfs


def _run(name):
    """Run a file as the board runs boot.py and main.py: in the __main__ module (so
    `import __main__` and unittest.main() find its names), both in the same globals (what
    boot.py defines, main.py sees), with sys.argv naming it as the unix port does."""
    path, source = _find(name)
    if source is None:
        return False
    import __main__

    env = __main__.__dict__
    env["__file__"] = path
    sys.argv[:] = [path]
    # The file's code made as a board makes it, in the heap's lowest free blocks (the
    # shim's finding and reading of it garbage first), and its source not kept (a board
    # reads it through the lexer): nothing of the shim's in the firmware's heap as it runs.
    global _compiling
    _hil._Link.collect()
    _compiling = path  # (a failure in here is the firmware's, before any line of it ran)
    code = compile(source, path, "exec")
    _compiling = source = None
    exec(code, env)
    return True


_compiling = None  # the firmware's file being compiled (_run), else None


TRACEBACK = "Traceback (most recent call last):"
FRAME = '  File "'


def _shim_folder():
    """The shim's folder as its modules were compiled (the one this function was compiled
    in, before the sandbox), read from a traceback of its own: kept nowhere, so no host path
    stays reachable (hil_tests/test_board_flash.py's walk)."""
    buf = io.StringIO()
    try:
        raise KeyError
    except KeyError as e:
        sys.print_exception(e, buf)
    for line in buf.getvalue().split("\n"):
        if line.startswith(FRAME):
            return line[len(FRAME) : line.index('"', len(FRAME))].rsplit("/", 1)[0] + "/"
    return None


def _board_traceback(text, compiling=False):
    """A traceback as the firmware's board prints it: the shim's own frames left out (its
    folder as compiled, and /_hil/, where the sandbox shows it; on a board those are C:
    machine, open, the boot that runs main.py), as _hil._exempt and _hilpoll.firmware_stack
    tell them, and asyncio's task queue (C on a board: _asyncio); the firmware's and the rest
    of asyncio's kept. One whose every frame is the shim's is the harness's own failure: kept
    whole; but not while the firmware's file compiles (``compiling``: a MemoryError in the
    parser, its heap too small): that one a board prints as the exception alone, with no
    frame and no header (py/obj.c, mp_obj_print_exception)."""
    lines = text.split("\n")
    if lines[0] != TRACEBACK:
        return text
    end = 1
    while end < len(lines) and lines[end].startswith(FRAME):
        end += 1
    shim = (_shim_folder() or "/_hil/", "/_hil/", "asyncio/task.py")  # (the task queue: C on a board)
    kept = [line for line in lines[1:end] if not line[len(FRAME) :].startswith(shim)]
    if not kept:
        return "\n".join(lines[end:]) if compiling else text
    return "\n".join([TRACEBACK] + kept + lines[end:])


def print_exception(exc, file=None):
    """The firmware's sys.print_exception: the C one's text with the shim's frames left
    out (:func:`_board_traceback`). Where there is no room for the text (a full heap, the
    heap locked), the C one's as it is: a board's needs none."""
    out = sys.stdout if file is None else file
    text = _traceback_text(exc)
    if text is None:
        sys.print_exception(exc, out)
    else:
        out.write(text)


def _traceback_text(exc, compiling=False):
    """:func:`_board_traceback` of ``exc``'s traceback; None where there is no room for it."""
    try:
        buf = io.StringIO()
        sys.print_exception(exc, buf)
        return _board_traceback(buf.getvalue(), compiling)
    except MemoryError:
        return None


def _board_print_exception():
    """The board's sys (_hilsys) prints a traceback as the board does; the unix port's own
    sys, a board of no known family's, is read-only and keeps the C one."""
    board = sys.modules.get("sys", sys)
    if board is not sys:
        board.print_exception = print_exception


def _heap_unlocked():
    # (no import statement: under heap_lock the board's import filter cannot run)
    _micropython.heap_lock()
    for _ in range(_micropython.heap_unlock()):
        _micropython.heap_unlock()


def _getenv():
    import os

    return getattr(os, "getenv", None)  # boards have no environment


def _confine():
    """The firmware's view made a board's: its flash at /, no host reach (_hilconfine)."""
    import _hilconfine

    _hilconfine.confine(_hil._Link.settings, __file__.rsplit("/", 1)[0])


def _give_way():
    """The firmware's own module of a board built-in's name takes it (_hilconfine.give_way)."""
    import _hilconfine

    _hilconfine.give_way()


def _coverage():
    """Firmware coverage when the host asks (HIL_COVERAGE_FD: _hilcov, docs/coverage.md)."""
    import os

    getenv = getattr(os, "getenv", None)
    fd = getenv("HIL_COVERAGE_FD") if getenv else None
    if not fd:
        return None
    import _hilcov

    shim = __file__.rsplit("/", 1)[0]
    _hilcov.start(fd, (shim + "/", "/_hil/", ".frozen"))
    return _hilcov


# The held pieces' data: 192 bytes (with its tuple and bytearray object, 256 in the heap)
# for the most, then a byte (three blocks) and a lone tuple (one) for the holes between
# the shim's objects.
BALLAST_DATA_BYTES = (192, 1)


def _firmware_room(want):
    """The firmware's heap_size (``want``) set apart as the shim starts, in one piece: the
    shim's own start-up (compiling machine, the board's flash, confinement) then runs in
    its share (host/rig/targets/heap.py) beside it. py/gc.c collects only when an allocation
    fails, so what the shim keeps from its start-up lies wherever the allocator stood
    then, across the whole heap; a firmware heap made afterwards from what is free would
    be in pieces between the shim's objects, where a board's fresh heap is one piece.
    (A collect first: the room goes in the lowest hole that holds it, gc_alloc's first fit.)"""
    if not want:
        return None
    import gc

    gc.collect()
    return [bytearray(want)]


def _board_heap(room):
    """The heap as the firmware's board has it. machine (with its buses, and rp2 on an
    RP2040) is imported first: on a board it is C in flash, so its code (compiled here,
    the shim's biggest moment) is no part of the firmware's heap. Then the shim's reserve
    is taken (_hil.make_room), and all else that is free in the interpreter's heap is
    held, in small pieces (py/gc.c's gc_alloc takes the first free blocks that fit, so
    they fill the holes the shim's start-up left), and the firmware's room
    (_firmware_room) is let go: the firmware's gc.mem_free() starts at its board's heap,
    in one piece, and a MemoryError comes where a board's does. Returns what is held."""
    import gc
    import machine  # noqa: F401

    import _hilbus  # noqa: F401  machine's buses (I2C, SPI), imported at their first use otherwise

    if sys.modules.get("sys", sys).platform == "rp2":  # (the board's sys: _hilsys) rp2, with its PIO assembler
        import rp2  # noqa: F401

    _hil.keep_reserve()
    if room is None:
        return None
    gc.collect()
    held = None
    for data in BALLAST_DATA_BYTES:
        try:
            while True:
                held = (held, bytearray(data))
        except MemoryError:
            pass
    try:
        while True:
            held = (held,)  # (a block: the last holes)
    except MemoryError:
        pass
    want = len(room[0])
    room[0] = None  # (its one reference: the list is the shim's, the bytearray gone at the collect)
    gc.collect()
    free = gc.mem_free()
    if free < want:
        raise MemoryError(
            "_hilboot: expected the firmware's heap of %d bytes free once its room was let go, got %d" % (want, free)
        )
    while free > want:  # (the room's bytearray object, a piece that failed halfway: a block each)
        held = (held,)
        free = gc.mem_free()
    return held


def _finish(coverage, kind, code=0, text=None):
    if coverage is not None:  # (before EXIT: then the host may end the process)
        _heap_unlocked()
        coverage.save()
    _hil.finish(kind, code, text)


def _failed(e, coverage, pil):
    """The firmware raised ``e``: its traceback to the console and to the host (FAULT).

    The firmware's frames, as its board prints them; but the watchdog's interrupt
    (host/rig/targets/target.py, _stack) keeps the whole stack, as the harness's word on where
    the firmware was: the shim's frames tell the host a wait on the link from a spin in the
    firmware's own code (a run that ends on one otherwise shows it as the firmware's:
    host/rig/loop/endings.py, board_traceback). With no room to leave the shim's out, the
    text as it is."""
    _heap_unlocked()  # (raised under heap_lock: the traceback still needs memory)
    if _hil._Link.reserve is not None:
        _hil.spend_reserve()  # (raised with the heap full: the same)
    compiling = _compiling
    if compiling is not None:  # (what the failed compile made is garbage: room for the text)
        _hil._Link.collect()
    text = None if isinstance(e, KeyboardInterrupt) else _traceback_text(e, compiling is not None)
    if text is None:
        buf = io.StringIO()
        sys.print_exception(e, buf)
        text = buf.getvalue()
    if not pil:  # on a board the console is the link: the traceback goes in FAULT
        sys.stderr.write(text)
    if compiling is not None and not isinstance(e, SyntaxError):  # (the host's word, beside the board's text:
        # where it was; a SyntaxError's text names the file and line already)
        text += "(raised while %s was compiled: none of it ran)\n" % compiling
    _finish(coverage, F.EXIT_SYSEXIT, 1, text)


def main(pil=False):
    coverage = None
    try:
        _hil.start()  # (in here: interrupted in the handshake, its stack still goes to the host)
        settings = _hil._Link.settings  # (WELCOME's: docs/protocol.md)
        room = None if pil else _firmware_room(settings["heap_bytes"])  # (0: the interpreter's whole heap)
        getenv = _getenv()  # (before _confine: os.getenv)
        _asyncio_in_virtual_time()
        entry = settings["entry"].decode()  # (the file a board runs after boot.py: main.py, or the rig file's)
        if not pil:  # (at a board's REPL, boot.py ran at power-on: its names are there)
            coverage = _coverage()
            _confine()
            _fresh_main()  # (before _board_heap: the -c command's names, freed, would be the firmware's)
            _board_print_exception()  # (before _board_heap too: the board's sys grows by a name)
            _hil._Link.ballast = _board_heap(room)
            _give_way()
            _port_boot()
            _hil.cpu_start(getenv)  # (MCU time: the firmware's compute costs from here)
            _run("boot.py")
        if not _run(entry):
            raise OSError("no %s on the firmware path" % entry)
    except _hil.ResetRequest as e:
        _finish(coverage, F.EXIT_RESET, e.args[0] if e.args else 0)  # (1: a wake from deep sleep)
        if not pil:
            sys.exit(0)
        return
    except _hil.HostStop:
        _finish(coverage, F.EXIT_RETURN)
        return
    except SystemExit as e:
        code = e.args[0] if e.args and isinstance(e.args[0], int) else 0
        _finish(coverage, F.EXIT_SYSEXIT, code)
        if pil:
            return
        raise
    except _hil.HostGone:
        if not pil:
            sys.exit(3)
        return
    except BaseException as e:  # noqa: BLE001  any firmware failure goes to the host
        _failed(e, coverage, pil)
        if not pil:
            sys.exit(1)
        return
    _finish(coverage, F.EXIT_RETURN)
