"""Processor in the loop: the firmware runs on a board, the plant runs here.

The same shim that runs inside the unix port runs on the board: :class:`BoardTarget`
copies it (and asyncio's pure-Python package, for its task queue) to the board's
``/hil`` folder with mpremote, soft-resets the board in its raw REPL, and starts
``_hilboot`` there. The plant link then runs over the board's own USB serial console:
frames both ways, and whatever the firmware prints in between is its console. Time is
lockstep (virtual, deterministic, compute measured with the board's own clock) or real
time (the board's real timing). ``Rig.stop()`` sends BYE; the firmware stops at its next
wait and the board is back at its REPL.

Tested against the virtual board of ``host/device/vboard.py`` (``hil_tests/test_pil.py``).
"""

import tempfile
import time
from pathlib import Path

from host.core import interpreter
from host.core.errors import FirmwareHung, LinkError
from host.core.paths import SHIM_DIR
from host.device import flash
from host.link import Channel, FdTransport
from host.link import frames as F
from host.rig import Recording, Rig, RigSpec
from host.rig.loop.spec import NO_RECORDING
from host.rig.targets.firmware import ShimSettings
from host.rig.targets.target import Target

SHIM_FILES = (
    "_hil.py",
    "_hilframe.py",
    "_hilboot.py",
    "_hilsys.py",
    "_hilboards.py",  # (a kit board's pin names: machine imports it for a board that is no Pico)
    "_hilpoll.py",  # (imported at a poll's first look only: machine.Pin.value, machine.mem*)
    "_hilrepl.py",  # (imported at the host's first EVAL only: docs/live.md)
    "_umachine.py",
    "machine.py",
    "time.py",
    "select.py",
)
ASYNCIO_FILES = ("__init__.py", "core.py", "event.py", "funcs.py", "lock.py", "stream.py", "task.py")
BOOT = (
    b"import sys, os\nsys.path.insert(0, os.getcwd().rstrip('/') + '/hil')\nimport _hilboot\n_hilboot.main(pil=True)\n"
)
RAW_BANNER = b"raw REPL; CTRL-B to exit\r\n"


def _board_mpy(port: str) -> tuple[int, int] | None:
    """The folders for the shim made, and the .mpy version the board loads (None: it says none)."""
    folders = "import os\nfor d in ('hil', 'hil/asyncio'):\n try:\n  os.mkdir(d)\n except OSError:\n  pass\n"
    return flash.mpy_of(flash._mpremote(port, "exec", folders + flash.MPY_PROBE))


def _compiled(src: Path, folder: Path) -> Path:
    dst = folder / (src.stem + ".mpy")
    flash.compile_module(src, dst)
    return dst


def asyncio_source() -> Path:
    """asyncio's own package, from the MicroPython source the harness was built from."""
    src = interpreter.build_root() / "src"  # (the default version's source: interpreter._src_root)
    for tree in sorted(src.glob("micropython-*")):
        folder = tree / "extmod" / "asyncio"
        if (folder / "task.py").is_file():
            return folder
    raise LinkError(f"no MicroPython source under {src} to take asyncio from: run `make setup`")


class BoardTarget(Target):
    """A board on a serial port: the shim runs there, the link is its USB serial console."""

    def __init__(self, port: str):
        self.port = port
        self.serial = None
        self._pending = b""
        self._chan = None

    def open(self, firmware, on_console) -> Channel:
        import serial

        flash.check_port(self.port)
        self._upload()
        self.serial = serial.Serial(self.port, 115200, timeout=0, exclusive=True)
        ser = self.serial
        ser.write(b"\r\x03\x03\x01")  # stop what runs, raw REPL
        self._expect(RAW_BANNER + b">", 5.0)
        ser.write(b"\x04")  # soft reset: a clean interpreter
        self._expect(b"soft reboot\r\n", 5.0)
        self._expect(RAW_BANNER + b">", 5.0)
        ser.write(BOOT + b"\x04")
        rest = self._expect(b"OK", 5.0)
        self._chan = Channel(FdTransport(ser.fileno()))
        self._chan.decoder.on_skip = on_console
        self._chan.decoder.feed(rest)  # the shim may already have said HELLO
        return self._chan

    def _upload(self) -> None:
        """The shim and asyncio to /hil on the board; mpremote skips what is there.

        Compiled with mpy-cross when the board loads its .mpy version (a board imports the
        shim's 350 kB of source only with a heap of some 300 kB; compiled, it fits in 60 kB,
        and half the bytes cross the serial), else as source. A compiled module's source
        left from an earlier upload is removed: a board imports ``x.py`` before ``x.mpy``."""
        version = _board_mpy(self.port)
        aio = asyncio_source()
        with tempfile.TemporaryDirectory(prefix="mpy-fil-pil-") as tmp:
            shim = [SHIM_DIR / f for f in SHIM_FILES]
            lib = [aio / f for f in ASYNCIO_FILES]
            compiled = version is not None and version == flash.mpy_cross_version()
            if compiled:
                shim = [_compiled(src, Path(tmp) / "hil") for src in shim]
                lib = [_compiled(src, Path(tmp) / "hil" / "asyncio") for src in lib]
            stale = [f"hil/{p.stem}.py" for p in shim] + [f"hil/asyncio/{p.stem}.py" for p in lib] if compiled else []
            flash._mpremote(
                self.port,
                "cp",
                *map(str, shim),
                ":hil/",
                "+",
                "cp",
                *map(str, lib),
                ":hil/asyncio/",
                "+",
                "exec",
                "import os\nfor f in %r:\n try:\n  os.remove(f)\n except OSError:\n  pass" % stale,
            )

    def _expect(self, marker: bytes, timeout_s: float) -> bytes:
        """Read up to marker; return what came after it."""
        data = self._pending
        deadline = time.monotonic() + timeout_s
        while marker not in data:
            if time.monotonic() > deadline:
                raise LinkError(
                    f"PORT={self.port}: expected {marker!r} from the board's REPL within {timeout_s:g} s, "
                    f"got {data[-200:]!r}"
                )
            chunk = self.serial.read(256)
            data += chunk
            if not chunk:
                time.sleep(0.005)
        rest = data[data.index(marker) + len(marker) :]
        self._pending = rest
        return rest

    def alive(self) -> bool:
        return self.serial is not None

    def shim_settings(self, firmware) -> ShimSettings:
        """A board's own UART, heap, CPU and flash are real: the shim is told the entry and
        the ticks' wrap (its clock is the loop's), and no console time (console_baud 0:
        its UART's own time is real, a modelled one would come on top)."""
        rig_file = firmware.shim_settings()
        return ShimSettings(entry=rig_file.entry, ticks_wrap_s=rig_file.ticks_wrap_s, console_baud=0)

    def close(self, session_open: bool = False) -> None:
        """BYE ends a session still open: the firmware stops at its next wait and the
        board is back at its REPL."""
        ser, self.serial = self.serial, None
        if ser is None:
            return
        try:
            if session_open and self._chan is not None:
                self._chan.send(F.BYE, b"")
                deadline = time.monotonic() + 3.0
                while time.monotonic() < deadline:
                    type_, _seq, _payload = self._chan.recv(max(0.0, deadline - time.monotonic()))
                    if type_ == F.EXIT:
                        break
            ser.write(b"\x02")  # back to the friendly REPL
        except (OSError, LinkError):
            pass
        finally:
            ser.close()

    def restart(self, firmware, on_console) -> Channel:
        raise LinkError(
            f"PORT={self.port}: the firmware reset the board (machine.reset()); the processor-in-the-loop session ended"
        )

    def on_silence(self, rig, timeout_s: float, what: str):
        rig.stop()
        raise FirmwareHung(
            f"PORT={self.port}: the board stopped answering: expected {what} within {timeout_s:g} s, got nothing "
            f"(virtual t={rig.t_us / 1e6:.6f} s).{rig.where()}"
        )


def board_rig(spec: RigSpec, recording: Recording = NO_RECORDING, *, port: str) -> Rig:
    """The rig ``spec`` describes, its firmware on the board at ``port`` (its files flashed there)."""
    rig = Rig(spec, recording, target=BoardTarget(port))
    rig.identity = None  # a real board: its own sys.platform and machine
    return rig
