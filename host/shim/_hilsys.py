# The board's modules as its firmware sees them, put in sys.modules by _hil.start (an
# `import` finds them there before the built-ins): sys with the board's sys.platform and
# sys.implementation._machine (firmware picks pins by them) when the host names the
# board, usys the same; micropython with alloc_emergency_exception_buf (a board's, here
# nothing to allocate); os with uname(), which the unix port leaves out, and ilistdir()
# with each file's size, as a board's VFS gives it. print() tells the shim it printed, so
# the host stamps the text with its virtual time (console.log, docs/traces.md). input()
# waits for the console in virtual time (a scenario's write-serial), as a board's does.
import micropython as _micropython
import os as _os
import sys as _sys
from collections import namedtuple

_Implementation = namedtuple("implementation", ("name", "version", "_machine", "_mpy", "_build"))
_Uname = namedtuple("uname_result", ("sysname", "nodename", "release", "version", "machine"))


class _Module:
    pass


def _copy(module):
    copy = _Module()
    for name in dir(module):
        if not name.startswith("__"):
            setattr(copy, name, getattr(module, name))
    return copy


def _alloc_emergency_exception_buf(size):
    pass


def _ilistdir(path="."):
    # a board's VFS gives (name, type, inode, size); the unix port's, three fields
    folder = path or "."
    for entry in _os.ilistdir(folder):
        size = _os.stat(folder + "/" + entry[0])[6] if entry[1] == 0x8000 else 0
        yield (entry[0], entry[1], entry[2], size)


class _Unset:
    pass


_UNSET = _Unset()  # an argument print() was not given
_said = _print = None  # the shim's hook and the built-in print (install)
before_print = None  # MCU time: _hil.pay_cpu (the compute before the print paid); with threads _hilthread.look
_counting = False  # print() costs the console UART's time: count what it writes


def _board_print(a=_UNSET, b=_UNSET, c=_UNSET, d=_UNSET, e=_UNSET, f=_UNSET, *more, sep=" ", end="\n", file=None):
    # print() as the firmware calls it: the built-in, then the shim told. Named parameters,
    # not *args (a tuple per call), and no closure (one allocates for five arguments or more):
    # up to six items print under micropython.heap_lock(), as the built-in does on a board.
    out = _sys.stdout if file is None else file
    if before_print is not None:
        before_print()
    if more:
        _print(a, b, c, d, e, f, *more, sep=sep, end=end, file=out)
    elif f is not _UNSET:
        _print(a, b, c, d, e, f, sep=sep, end=end, file=out)
    elif e is not _UNSET:
        _print(a, b, c, d, e, sep=sep, end=end, file=out)
    elif d is not _UNSET:
        _print(a, b, c, d, sep=sep, end=end, file=out)
    elif c is not _UNSET:
        _print(a, b, c, sep=sep, end=end, file=out)
    elif b is not _UNSET:
        _print(a, b, sep=sep, end=end, file=out)
    elif a is not _UNSET:
        _print(a, sep=sep, end=end, file=out)
    else:
        _print(sep=sep, end=end, file=out)
    if _counting and (file is None or file is _sys.stdout):
        _said(_printed_bytes(a, b, c, d, e, f, more, sep, end))
    else:
        _said()


def _item_bytes(x):
    # the characters print() wrote for x (a str's own length allocates nothing)
    if type(x) is str:
        return len(x)
    try:
        return len(str(x))
    except MemoryError:  # under heap_lock(): a number's digits cannot be counted
        return 8


def _printed_bytes(a, b, c, d, e, f, more, sep, end):
    # what print() sent to the console, separators and end included (no tuple: this runs
    # under heap_lock() too)
    n = len(end) - len(sep)
    if a is _UNSET:
        return n + len(sep)
    n += _item_bytes(a) + len(sep)
    if b is not _UNSET:
        n += _item_bytes(b) + len(sep)
        if c is not _UNSET:
            n += _item_bytes(c) + len(sep)
            if d is not _UNSET:
                n += _item_bytes(d) + len(sep)
                if e is not _UNSET:
                    n += _item_bytes(e) + len(sep)
                    if f is not _UNSET:
                        n += _item_bytes(f) + len(sep)
                        for x in more:
                            n += _item_bytes(x) + len(sep)
    return n


_input = None  # the built-in input (install)
TICK_US = 1000  # a board's system tick: how often a wait for the console looks again


def _console_ready():
    # a byte waits on the console's input (the unix port's stdin: a scenario's write-serial)
    import _hil

    p = _hil._rselect.poll()
    p.register(_sys.stdin, _hil._rselect.POLLIN)
    return bool(p.poll(0))


def _hil_link():
    import _hil

    return _hil._link


def _StdioLinkType():
    import _hil

    return _hil._StdioLink


def _wait_console():
    import _hil

    while not _console_ready():
        _hil.blocking()
        _hil.run_until(_hil.now() + TICK_US)


class _BoardStdin:
    # sys.stdin as a board's: a read waits in virtual time for the bytes typed on the
    # console (a scenario's write-serial); select.poll asks it (_poll_ready) each tick.
    # Text, and its .buffer the same in bytes.
    def __init__(self, binary=False):
        self._binary = binary
        self.buffer = self if binary else _BoardStdin(True)

    def _poll_ready(self, mask):
        return _console_ready()

    def fileno(self):
        return _sys.stdin.fileno()

    def _out(self, data):
        return data if self._binary else data.decode()

    def read(self, n=-1):
        # n bytes (waiting for each); n < 0: what is there once something is
        data = b""
        while n < 0 or len(data) < n:
            _wait_console()
            c = _sys.stdin.buffer.read(1)
            if not c:
                break
            data += c
            if n < 0 and not _console_ready():
                break
        return self._out(data)

    def readline(self):
        line = b""
        while True:
            _wait_console()
            c = _sys.stdin.buffer.read(1)
            line += c
            if not c or c == b"\n":
                break
        return self._out(line)


def _board_input(prompt=None):
    # input() as on a board: waits in virtual time, a system tick at a time, for each
    # character typed on the console, and echoes the line (a board's readline does)
    import _hil

    if isinstance(_hil_link(), _StdioLinkType()):  # (the console is the link itself)
        return _input(prompt) if prompt is not None else _input()
    if prompt:
        _board_print(prompt, end="")
    line = b""
    while True:
        while not _console_ready():
            _hil.blocking()
            _hil.run_until(_hil.now() + TICK_US)
        c = _sys.stdin.buffer.read(1)
        if not c:  # (the console closed: what a board never does; the line so far)
            break
        if c == b"\n":
            break
        if c != b"\r":
            line += c
    text = line.decode()
    _board_print(text)
    return text


def install(said, counting=False, platform=None, machine=None):
    import builtins

    global _said, _print, _counting, _input
    _said, _print, _counting = said, builtins.print, counting
    builtins.print = _board_print
    _input, builtins.input = builtins.input, _board_input
    impl = _sys.implementation
    version = ".".join(str(v) for v in impl.version[:3])
    if platform:
        board = _copy(_sys)
        board.platform = platform
        # sys.executable is the unix port's alone (py/modsys.c: MICROPY_PY_SYS_EXECUTABLE);
        # a board's sys has none, and here it would name a host path
        if hasattr(board, "executable"):
            del board.executable
        if not isinstance(_hil_link(), _StdioLinkType()):  # (on a board the console is the link)
            board.stdin = _BoardStdin()
        board.implementation = _Implementation(
            impl.name, impl.version, machine, getattr(impl, "_mpy", 0), getattr(impl, "_build", "")
        )
        _sys.modules["sys"] = board
    _sys.modules["usys"] = _sys.modules.get("sys", _sys)
    mp = _copy(_micropython)
    mp.alloc_emergency_exception_buf = _alloc_emergency_exception_buf
    import _hil

    # the board's scheduler (its queue's depth, callbacks only where the port runs them):
    # the unix port's own would run them inside the shim's calls, four at most
    mp.schedule = _hil.mp_schedule
    _sys.modules["micropython"] = mp
    board_os = _copy(_os)
    uname = _Uname(
        platform or _sys.platform,
        platform or _sys.platform,
        version,
        "v%s on 2025-05-04" % version,
        machine or impl._machine,
    )
    board_os.uname = lambda: uname
    board_os.ilistdir = _ilistdir
    _sys.modules["os"] = board_os
    _sys.modules["uos"] = board_os
