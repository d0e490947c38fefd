"""One MicroPython test file run in the loop, as ``micropython [-X k=v ...] file.py``
would run it: the file is the firmware's entry file, its folder the board's ``/``, the
plant a bench of wires (a ``bench`` body with ``wire`` and ``uart_wire`` parts). What the firmware printed goes to
stdout and the exit status is the firmware's (1 for an uncaught exception), so
upstream's ``run-tests.py`` can use this as its ``MICROPY_MICROPYTHON``.

Anything else (``-c``, other options) runs on the plain interpreter, and so do
``run-tests.py``'s feature checks but ``target_info.py``: they ask the interpreter what it
has (big ints, sets, async, complex, f-strings ...), and the loop runs that same binary;
``target_info.py`` names the platform, which in the loop is the board's. (Compared once
for each board: the same output in the loop and plain, but for the inline assemblers'
tracebacks, which fail either way.) They are 16 of every run's first 17 runs, and a run
in the loop costs about a second: the harness's import and the rig's start.

The harness is imported only for a run in the loop: a plain run starts at once.
"""

import json
import os
import socket
import sys
from pathlib import Path

from host.core import interpreter

# The bench: pin pairs joined by a wire (output pin -> input pin), on every board; GPIO4
# to GPIO5 and GPIO12 to GPIO13 are upstream's esp32 target wiring.
PINS = {"W0_OUT": 4, "W0_IN": 5, "W1_OUT": 12, "W1_IN": 13, "W2_OUT": 18, "W2_IN": 19, "W3_OUT": 25, "W3_IN": 26}
PINS |= {"U0_UART": 0, "U1_UART": 1, "U2_UART": 2}  # each UART's TX wired to its RX
WIRING = {
    "U0_UART": "u0.line",
    "U1_UART": "u1.line",
    "U2_UART": "u2.line",
    "W0_OUT": "w0.in",
    "W0_IN": "w0.out",
    "W1_OUT": "w1.in",
    "W1_IN": "w1.out",
    "W2_OUT": "w2.in",
    "W2_IN": "w2.out",
    "W3_OUT": "w3.in",
    "W3_IN": "w3.out",
}
BENCH = {
    "body": "bench",
    "parts": [{"kind": "wire", "name": f"w{i}"} for i in range(4)]
    + [{"kind": "uart_wire", "name": f"u{i}"} for i in range(3)],
}
"""The bench as a rig file's ``[plant]`` table: four wires and three UART loops."""
BENCH_LIB = Path(__file__).resolve().parent / "bench"
LIMIT_S = 120.0  # virtual seconds a test may run
BOARD_ENV = "MPY_FIL_BOARD"  # a board family (esp32, rpi_pico): its sys.platform; unset: the unix port's


IN_THE_LOOP_CHECKS = ("target_info.py",)  # feature checks whose answer is the board's


def preload() -> None:
    """Import what a run in the loop needs (the functions below import it when called):
    the conformance server does, once, before it forks a child per file."""
    import host.rig.config.app  # noqa: F401
    import host.rig.loop.rig  # noqa: F401
    import host.rig.loop.spec  # noqa: F401
    import host.rig.scan.boards  # noqa: F401
    import sim_plant.catalogue.assembly  # noqa: F401


def bench_plant(**options):
    """The bench's plant (``options``: ``<part>.<option>`` keys, as a world's)."""
    from sim_plant.catalogue.assembly import assemble

    return assemble({**BENCH, **options})


def bench_app(test: Path, heap_size: str | None = None):
    from host.rig.config.app import App, BoardSettings, Code, InterpreterSettings
    from host.rig.scan.boards import identity
    from host.rig.targets.boardfs import Confinement

    board = os.environ.get(BOARD_ENV, "")
    return App(
        name="conformance",
        default_board=board or "bench",
        make_plant=bench_plant,
        wiring=WIRING,
        # target_wiring.py in BENCH_LIB, for upstream's hardware tests
        code=Code(folder=test.parent, entry=test.name, harness_lib=False, lib_dirs=(BENCH_LIB,)),
        # MicroPython's own tests, not a firmware under test: the select tests poll sockets
        # (the shim's select serves them); in the sandbox only its own loopback is there
        board=BoardSettings(
            pins=PINS, identity=identity(board) if board else None, confine=Confinement(allow=("socket",))
        ),
        interpreter=InterpreterSettings(heap_size=heap_size),
    )


def parse(argv: list[str]) -> tuple[Path, str | None] | None:
    """(the test file, -X heapsize) for `[-X k=v ...] file.py`; None for anything else."""
    heap = None
    args = list(argv)
    while len(args) >= 2 and args[0] == "-X":
        key, _, value = args[1].partition("=")
        if key == "heapsize":
            heap = value
        elif key != "emit" or value != "bytecode":
            return None
        args = args[2:]
    if len(args) != 1 or not args[0].endswith(".py"):
        return None
    path = Path(args[0])
    if path.parent.name == "feature_check" and path.name not in IN_THE_LOOP_CHECKS:
        return None  # (the interpreter's own features: the same binary as in the loop)
    return path.resolve(), heap


def run(test: Path, heap: str | None) -> tuple[str, int]:
    """(what the firmware printed, its exit status)."""
    from host.core.errors import HarnessError
    from host.link.transport import busy_poll_wanted
    from host.rig.loop.rig import Rig
    from host.rig.loop.spec import RigSpec

    spec = RigSpec(bench_app(test, heap), watchdog_s=10.0, allow_exit=True, busy_poll=busy_poll_wanted())
    rig = Rig(spec)
    status, note = 0, ""
    try:
        rig.start()
        deadline = rig.t_us + round(LIMIT_S * 1e6)
        while rig.exit_kind is None and rig.t_us < deadline:
            rig.run_for(1.0)
        if rig.exit_kind is None:
            status, note = 1, f"\nTIMEOUT: still running after {LIMIT_S:g} virtual s\n"
        else:
            status = rig.exit_code or 0
    except HarnessError as e:  # the firmware raised (its traceback is on the console) or hung
        status = 1
        note = "" if "Traceback" in rig.console else f"\n{e}\n"
    finally:
        rig.stop()
    return rig.console + note, status


SOCKET_ENV = "MPY_FIL_CONFORMANCE_SERVER"  # the server's socket (host/conformance/forkserver.py), for the wrapper


def read_all(conn) -> bytes:
    chunks = []
    while True:
        chunk = conn.recv(65536)
        if not chunk:
            return b"".join(chunks)
        chunks.append(chunk)


def ask(path: str, argv: list[str]) -> dict:
    """Run ``argv`` (a test file's, as :func:`parse` takes it) on the server at
    ``path``: {"console", "status", "stdout", "stderr"}."""
    request = {"argv": argv, "cwd": os.getcwd(), "board": os.environ.get(BOARD_ENV, "")}
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as conn:
        conn.connect(path)
        conn.sendall(json.dumps(request).encode())
        conn.shutdown(socket.SHUT_WR)
        reply = read_all(conn)
    if not reply:
        raise SystemExit(f"error: the conformance server at {path} ended without an answer")
    return json.loads(reply)


def main(argv: list[str]) -> int:
    parsed = parse(argv)
    if parsed is None:
        plain = str(interpreter.find())
        os.execv(plain, [plain, *argv])
    server = os.environ.get(SOCKET_ENV)
    if server:  # (python -m host.conformance's server: the harness imported once)
        reply = ask(server, argv)
        sys.stderr.write(reply["stderr"])
        sys.stderr.flush()
        console, status = reply["stdout"] + reply["console"], reply["status"]
    else:
        console, status = run(*parsed)
    sys.stdout.write(console)
    sys.stdout.flush()
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
