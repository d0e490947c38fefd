"""A host program as a board (``docs/multi-board.md``, "A host program as a board"): a CPython
function standing in for one board of a set (a Linux master over I2C, a ROS-style node on a
UART), on the set's one virtual clock, talking over the same wires as a board's firmware.

The program runs in a thread of its own, but never alongside the set: each call that needs
the clock or the plant (a sleep, a bus transfer, a UART read that waits) hands a message to
the set and blocks until the set answers, as a board's shim blocks on its link. The set
reads those messages in its fixed order, so a run is as deterministic as one of firmware.

What the program gets (:class:`HostBoard`): ``ticks_us``/``ticks_ms``/``t_us`` (its virtual
time), ``sleep_ms``/``sleep_us``, ``print``, ``i2c(bus)`` (the controller's side of a
``board_i2c`` part: ``readfrom_mem``, ``readfrom_mem_into``, ``writeto_mem``, ``readfrom``,
``writeto``, ``scan``, each taking its time on the bus) and ``uart(signal, baudrate)`` (a
plant UART signal, a ``board_uart``'s end: ``write``, ``any``, ``read``, ``readline`` with a
timeout).
"""

import ctypes
import hashlib
import importlib.util
import queue
import sys
import threading
import traceback
from pathlib import Path

from host.core.errors import ConfigError, FirmwareError, FirmwareHung
from host.link import frames as F
from host.rig.loop.clock import Wait

ENODEV, EIO = 19, 5
STOP_CALL_S = 0.2
"""How long stop waits for the program's thread to take its stop at a call to the board;
then it is stopped at its next bytecode (a program computing without calling the board)."""
STOP_JOIN_S = 2.0


class _Stopped(BaseException):
    """Raised in the program's thread at its next call once the set stops (never caught
    by the program's own ``except Exception``)."""


def load_program(path: Path, function: str = "main"):
    """The function ``function`` of the Python file at ``path`` (its folder first on the
    import path while it loads, for its own modules)."""
    path = Path(path)
    if not path.is_file():
        raise ConfigError(f"{path}: no such host program (a Python file with a function {function}(board))")
    name = f"_mpy_fil_host_program_{hashlib.sha256(str(path).encode()).hexdigest()[:8]}"
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.path.insert(0, str(path.parent))
    try:
        spec.loader.exec_module(module)
    except Exception as e:  # noqa: BLE001  (the program's own error, named)
        raise ConfigError(f"{path}: the host program failed to load: {type(e).__name__}: {e}") from None
    finally:
        sys.path.remove(str(path.parent))
    main = getattr(module, function, None)
    if not callable(main):
        raise ConfigError(f"{path}: expected a function {function}(board) in the host program")
    return main


class _Clock:
    """What the set reads of a board's clock: its wait (None while it runs), the bound the
    set gives it, and serve (the set's instant reached)."""

    def __init__(self, program: "HostProgram"):
        self.program = program
        self.wait: Wait | None = None
        self.bound_us = 0
        self.end_us = 0

    def serve(self, t_us: int) -> None:
        program = self.program
        for _t, name, value in program.view.advance_to(t_us):
            program._arrived(name, value)
        wait = self.wait
        if wait.t_until <= t_us or (wait.watch and program._rx_ready(wait.watch)):
            self.wait = None
            program.t_us = t_us
            program._answer(t_us)


class HostProgram:
    """One board of a set that is a host program (a function ``main(board)``); the set
    calls what it calls of a :class:`~host.rig.loop.rig.Rig`."""

    def __init__(self, name: str, main, view, artefacts: Path | None, watchdog_s: float):
        self.name = name
        self._main = main
        self.view = view
        self.artefacts = Path(artefacts) if artefacts else None
        self.watchdog_s = watchdog_s
        self.clock = _Clock(self)
        self.exit_kind = None
        self.recorder = None
        self.t_us = view.t_us
        self.wiring = _NoWiring()
        self.session = self
        self._to_set: queue.Queue = queue.Queue()
        self._from_set: queue.Queue = queue.Queue()
        self._thread: threading.Thread | None = None
        self._lines: list[str] = []
        self._records = hashlib.sha256()
        self._rx: dict[str, bytes] = {}  # UART signal -> bytes arrived, not yet read

    # -- what the set calls -------------------------------------------------------------

    def start(self) -> None:
        self._thread = threading.Thread(target=self._run, name=f"host program {self.name}", daemon=True)
        self._thread.start()

    def stop(self, interrupted=None) -> None:
        thread = self._thread
        if thread is not None and thread.is_alive():
            self._from_set.put(("stop", None))  # (at its next call to the board)
            thread.join(STOP_CALL_S)
            if thread.is_alive():  # computing without a call to the board: stopped where it is
                ctypes.pythonapi.PyThreadState_SetAsyncExc(ctypes.c_ulong(thread.ident), ctypes.py_object(_Stopped))
                thread.join(STOP_JOIN_S)
        if self.artefacts is not None:
            self.artefacts.mkdir(parents=True, exist_ok=True)
            (self.artefacts / "console.log").write_text(self.console)

    def recv(self, timeout_s: float, what: str):
        try:
            return self._to_set.get(timeout=timeout_s)
        except queue.Empty:
            raise FirmwareHung(
                f"the host program sent nothing for {timeout_s:g} s of wall time at virtual t={self.t_us / 1e6:.6f} s "
                f"(waiting for {what}): it computes without sleeping, or waits on something outside the set"
            ) from None

    def to_wait(self, what: str = "a message") -> None:
        """Serve the program until it blocks in a wait, or ends (as ``Rig.to_wait``)."""
        while self.clock.wait is None and self.exit_kind is None:
            self.dispatch(*self.recv(self.watchdog_s, what))

    def dispatch(self, kind: str, payload) -> None:
        if kind == "wait":
            t_until, watch = payload
            self.clock.wait = Wait(self.t_us, max(t_until, self.t_us), watch)
            self._record("wait", t_until)
        elif kind == "bus":
            bus, op, address, n_read, data = payload
            reply = self.view.bus_transfer(bus, op, address, n_read, data)
            self._record("bus", bus, op, address, n_read, data.hex(), reply[0], reply[1], reply[2].hex())
            self._answer(reply)
        elif kind == "uart_tx":
            signal, data, baud = payload
            self.view.send_bytes(signal, data, baud)
            self._record("uart_tx", signal, data.hex())
        elif kind == "uart":
            self.view.signals = self.view.signals | {payload}
            self._answer(None)
        elif kind == "print":
            self._lines.append(payload)
            self._record("print", payload)
        elif kind == "end":
            self.exit_kind = F.EXIT_RETURN
            self._lines.append(f"(the host program returned at t={self.t_us / 1e6:.6f} s)\n")
        elif kind == "fault":
            self.exit_kind = F.EXIT_RETURN
            where = f"; artefacts: {self.artefacts}" if self.artefacts else ""
            raise FirmwareError(f"the host program raised at virtual t={self.t_us / 1e6:.6f} s:\n{payload}{where}")

    @property
    def console(self) -> str:
        return "".join(self._lines)

    @property
    def trace_digest(self) -> str:
        """What the program did, in order, with its instants (its prints, waits, transfers)."""
        return self._records.hexdigest()

    # -- the program's side (its thread) -------------------------------------------------

    def _run(self) -> None:
        try:
            self._main(HostBoard(self))
        except _Stopped:
            return
        except BaseException:  # noqa: BLE001  (the program's, sent to the set to fail the run)
            self._to_set.put(("fault", traceback.format_exc()))
            return
        self._to_set.put(("end", None))

    def _ask(self, kind: str, payload):
        """Hand the set a message and wait for its answer (the program's thread)."""
        self._to_set.put((kind, payload))
        what, value = self._from_set.get()
        if what == "stop":
            raise _Stopped()
        return value

    def _tell(self, kind: str, payload) -> None:
        self._to_set.put((kind, payload))

    def _answer(self, value) -> None:
        self._from_set.put(("answer", value))

    def _record(self, *what) -> None:
        self._records.update(repr((self.t_us, *what)).encode())

    def _arrived(self, name: str, value) -> None:
        if isinstance(value, (bytes, bytearray)):
            self._rx[name] = self._rx.get(name, b"") + bytes(value)

    def _rx_ready(self, watch) -> bool:
        return any(self._rx.get(s) for s in watch)


class _NoWiring:
    """(A host program has no pins: no handles, no I2C target.)"""

    wired = frozenset()
    i2c_targets: dict = {}
    handles: list = []


class HostBoard:
    """What a host program is given: its board's clock, console, I2C buses and UARTs."""

    def __init__(self, program: HostProgram):
        self._p = program
        self.name = program.name

    def ticks_us(self) -> int:
        return self._p.t_us

    def ticks_ms(self) -> int:
        return self._p.t_us // 1000

    @property
    def t_us(self) -> int:
        return self._p.t_us

    def sleep_us(self, us: int) -> None:
        self._wait_until(self._p.t_us + max(0, int(us)))

    def sleep_ms(self, ms: int) -> None:
        self.sleep_us(int(ms) * 1000)

    def _wait_until(self, t_us: int, watch=frozenset()) -> None:
        self._p._ask("wait", (t_us, frozenset(watch)))

    def print(self, *args, sep: str = " ", end: str = "\n") -> None:
        self._p._tell("print", sep.join(map(str, args)) + end)

    def i2c(self, bus: str = "i2c0", freq: int = 400_000) -> "HostI2C":
        return HostI2C(self, bus, freq)

    def uart(self, signal: str, baudrate: int = 115_200) -> "HostUART":
        self._p._ask("uart", signal)
        return HostUART(self, signal, baudrate)


class HostI2C:
    """The controller's side of a ``board_i2c`` part (or of the plant's chips on ``bus``),
    as machine.I2C's methods are: an address nobody acknowledges raises ``OSError(ENODEV)``,
    a written byte not acknowledged ``OSError(EIO)``. Each transfer then takes its time on
    the bus: 9 clocks a byte and the address byte of each direction, 2 for start and stop."""

    def __init__(self, board: HostBoard, bus: str, freq: int):
        self._board, self._bus, self._freq = board, bus, int(freq)

    def _xfer(self, address: int, data: bytes, n_read: int, stop: bool = True) -> bytes:
        op = F.BUS_XFER if stop else F.BUS_XFER_NOSTOP
        status, _count, got = self._board._p._ask("bus", (self._bus, op, address, n_read, bytes(data)))
        phases = (1 if data or not n_read else 0) + (1 if n_read else 0)
        clocks = 9 * (len(data) + n_read + phases) + 2
        self._board.sleep_us(-(-clocks * 1_000_000 // self._freq))
        if status == F.BUS_NACK_ADDRESS:
            raise OSError(ENODEV)
        if status != F.BUS_OK:
            raise OSError(EIO)
        return got

    def scan(self) -> list:
        _status, _count, got = self._board._p._ask("bus", (self._bus, F.BUS_SCAN, 0, 0, b""))
        return list(got)

    def readfrom(self, address: int, n: int, stop: bool = True) -> bytes:
        return self._xfer(address, b"", n, stop)

    def writeto(self, address: int, data, stop: bool = True) -> None:
        self._xfer(address, bytes(data), 0, stop)

    def readfrom_mem(self, address: int, reg: int, n: int, addrsize: int = 8) -> bytes:
        return self._xfer(address, reg.to_bytes(addrsize // 8, "big"), n)

    def readfrom_mem_into(self, address: int, reg: int, buf, addrsize: int = 8) -> None:
        buf[:] = self.readfrom_mem(address, reg, len(buf), addrsize)

    def writeto_mem(self, address: int, reg: int, data, addrsize: int = 8) -> None:
        self._xfer(address, reg.to_bytes(addrsize // 8, "big") + bytes(data), 0)


class HostUART:
    """A plant UART signal (a ``board_uart``'s end): bytes written take their time on the
    line (the plant times them at ``baudrate``); bytes that arrived are read."""

    def __init__(self, board: HostBoard, signal: str, baudrate: int):
        self._board, self._signal, self._baud = board, signal, int(baudrate)

    def write(self, data) -> int:
        data = data.encode() if isinstance(data, str) else bytes(data)
        self._board._p._tell("uart_tx", (self._signal, data, self._baud))
        return len(data)

    def any(self) -> int:
        return len(self._board._p._rx.get(self._signal, b""))

    def read(self, n: int = -1) -> bytes:
        rx = self._board._p._rx
        data = rx.get(self._signal, b"")
        n = len(data) if n < 0 else n
        rx[self._signal] = data[n:]
        return data[:n]

    def readline(self, timeout_ms: int = 1000) -> bytes:
        """A line (to its b"\\n"), waiting in virtual time up to ``timeout_ms`` for it; what
        has come when the time is up (maybe nothing)."""
        deadline = self._board.t_us + int(timeout_ms) * 1000
        while True:
            data = self._board._p._rx.get(self._signal, b"")
            if b"\n" in data:
                return self.read(data.index(b"\n") + 1)
            if self._board.t_us >= deadline:
                return self.read()
            self._board._wait_until(deadline, {self._signal})
