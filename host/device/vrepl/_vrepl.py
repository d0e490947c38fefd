# The virtual board's REPL, in MicroPython: what a board's pyexec does, over stdin and
# stdout (a pty the virtual board's host bridges to the "USB serial" port).
#
# Friendly REPL and raw REPL, raw-paste mode with flow control, Ctrl-C/Ctrl-D/Ctrl-A/
# Ctrl-B/Ctrl-E as on a board. A soft reset ends this process with an exit code that
# tells the host how to come back (raw or friendly REPL); the host starts a fresh
# interpreter in the same board folder, which runs boot.py, then main.py (friendly only).
import os
import sys

SOFT_RESET_RAW = 10
SOFT_RESET_FRIENDLY = 11
HARD_RESET = 12
RAW_PASTE_WINDOW = 256

_in = sys.stdin.buffer
_out = sys.stdout.buffer
_globals = {"__name__": "__main__"}


def _w(data):
    _out.write(data if isinstance(data, bytes) else data.encode())


def _rd():
    while True:
        try:
            c = _in.read(1)
        except KeyboardInterrupt:  # the host turns Ctrl-C into SIGINT
            return 3
        if c:
            return c[0]
        raise SystemExit(0)  # the host closed the console


def _print_exc(e):
    if type(e).__name__ == "ResetRequest":  # machine.reset() from the shim
        sys.exit(HARD_RESET)
    sys.print_exception(e, sys.stdout)


def _run_file(name):
    try:
        with open(name) as f:
            source = f.read()
    except OSError:
        return
    try:
        exec(compile(source, name, "exec"), _globals)
    except SystemExit:
        raise
    except BaseException as e:  # noqa: BLE001  a board prints it and goes on to the REPL
        _print_exc(e)


def _execute(source, single=False, raw=False):
    """Compile and run REPL input; True if it asked for a soft reset (SystemExit).

    In the raw REPL the output ends with \x04, then the exception text (if any)
    follows, ended by a second \x04, as a board's pyexec does."""
    error = None
    try:
        code = compile(source, "<stdin>", "single" if single else "exec")
        exec(code, _globals)
    except SystemExit:
        if raw:
            _w(b"\x04\x04")
        return True
    except BaseException as e:  # noqa: BLE001
        error = e
    if raw:
        _w(b"\x04")
    if error is not None:
        _print_exc(error)
    if raw:
        _w(b"\x04")
    return False


def _soft_reset(raw):
    _w("MPY: soft reboot\r\n")
    sys.exit(SOFT_RESET_RAW if raw else SOFT_RESET_FRIENDLY)


def raw_repl():
    _w("raw REPL; CTRL-B to exit\r\n")
    while True:
        line = bytearray()
        _w(">")
        while True:
            c = _rd()
            if c == 1:  # Ctrl-A: raw-paste request ("\x05A\x01") or raw REPL reset
                if len(line) == 2 and line[0] == 5:
                    if line[1] != ord("A"):
                        _w(b"R\x00")
                    else:
                        _raw_paste()
                    line = bytearray()
                    _w(">")
                    continue
                _w("raw REPL; CTRL-B to exit\r\n")
                line = bytearray()
                _w(">")
            elif c == 2:  # Ctrl-B: friendly REPL
                _w("\r\n")
                return
            elif c == 3:
                line = bytearray()
            elif c == 4:
                break
            else:
                line.append(c)
        _w("OK")
        if not line:
            _w("\r\n")
            _soft_reset(True)
        stop = _execute(bytes(line).decode(), raw=True)
        if stop:
            _soft_reset(True)


def _raw_paste():
    _w(b"R\x01" + bytes((RAW_PASTE_WINDOW & 0xFF, RAW_PASTE_WINDOW >> 8)) + b"\x01")
    data = bytearray()
    remain = RAW_PASTE_WINDOW
    while True:
        c = _rd()
        if c == 4 or c == 3:
            _w(b"\x04")
            break
        data.append(c)
        remain -= 1
        if remain == 0:
            _w(b"\x01")
            remain = RAW_PASTE_WINDOW
    if c == 3:
        return
    stop = _execute(bytes(data).decode(), raw=True)
    if stop:
        _soft_reset(True)


def _banner():
    impl = sys.implementation
    version = ".".join(str(v) for v in impl.version[:3])
    board = os.getenv("HIL_BOARD_NAME") or "virtual board"
    _w("MicroPython v%s on virtual board; %s with unix port\r\n" % (version, board))
    _w('Type "help()" for more information.\r\n')


def friendly_repl():
    _banner()
    while True:
        source = _read_input(">>> ")
        if source is None:  # Ctrl-D on an empty line
            _w("\r\n")
            _soft_reset(False)
        if source == "\x01":
            _w("\r\n")
            return
        if source.strip():
            if _execute(source, single=source.count("\n") == 0):
                _soft_reset(False)


def _read_input(prompt):
    """One (possibly compound) statement; None for Ctrl-D, "\x01" for Ctrl-A."""
    lines = []
    line = bytearray()
    _w(prompt)
    while True:
        c = _rd()
        if c == 13 or c == 10:
            _w("\r\n")
            text = bytes(line).decode()
            lines.append(text)
            line = bytearray()
            if len(lines) == 1 and not text.rstrip().endswith(":"):
                return text
            if len(lines) > 1 and not text.strip():
                return "\n".join(lines)
            _w("... ")
        elif c == 3:
            _w("\r\n")
            lines, line = [], bytearray()
            _w(prompt)
        elif c == 4:
            if not lines and not line:
                return None
        elif c == 1:
            return "\x01"
        elif c == 2:
            _w("\r\n")
            _banner()
            _w(prompt)
        elif c == 5:
            return _paste_mode()
        elif c in (8, 127):
            if line:
                line = line[:-1]
                _w(b"\x08 \x08")
        elif c >= 32 or c == 9:
            line.append(c)
            _out.write(bytes((c,)))


def _paste_mode():
    _w("\r\npaste mode; Ctrl-C to cancel, Ctrl-D to finish\r\n=== ")
    data = bytearray()
    while True:
        c = _rd()
        if c == 3:
            _w("\r\n")
            return ""
        if c == 4:
            _w("\r\n")
            return bytes(data).decode().replace("\r", "\n")
        data.append(c)
        _w(b"\r\n=== " if c == 13 else bytes((c,)))


def main():
    import micropython

    micropython.kbd_intr(3)  # Ctrl-C (SIGINT from the host) raises KeyboardInterrupt
    raw = os.getenv("HIL_REPL_MODE") == "raw"
    if os.getenv("HIL_LINK"):  # a wired virtual board: machine/time go to the plant
        import _hil

        _hil.start()
    _run_file("boot.py")
    if not raw:
        _run_file("main.py")
    while True:
        try:
            if raw:
                raw_repl()
                raw = False
            else:
                friendly_repl()
                raw = True
        except KeyboardInterrupt:  # a Ctrl-C between two reads: start the prompt again
            _w("\r\n")


main()
