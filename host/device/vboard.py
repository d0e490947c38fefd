"""A virtual board: MicroPython's unix port behaving like a board on a serial port.

The "USB serial" is a pty whose slave path tools open like ``/dev/ttyUSB0``
(``mpremote connect <port>``). Behind it the unix port runs the board REPL of
``host/device/vrepl/_vrepl.py`` (friendly REPL, raw REPL, raw-paste) in a board folder that
persists: ``build/vboard/<board>/fs`` holds what was flashed. A soft reset (Ctrl-D)
restarts the interpreter in the same folder; ``boot.py`` and then ``main.py`` run at
boot as on a board. Ctrl-C from the port interrupts what runs (SIGINT to the
interpreter), except while a plant-link session runs over the console (processor in the
loop), when the byte is passed through as data, as a board does after
``micropython.kbd_intr(-1)``.

A *wired* virtual board also has a robot: its ``machine`` and ``time`` are the shim,
served in real time by a plant (the app's, as in the HIL runs), so ``main.py`` drives a
simulated robot like a board on a bench. A *bare* one has the unix port's own modules,
for processor-in-the-loop runs where the host serves the plant over the port.

``python -m host.device.vboard start|stop|port|serve`` manages one per board folder.

Who ends it (docs/flash.md): a server belongs to the command that started it. Started by
:func:`start_background` (``make flash``, the tests' fixtures) it gets SIGTERM when that
command ends, however it ends, and stops with its interpreter; only ``vboard start``
detaches one on purpose, which ends at ``vboard stop`` or after ``IDLE_EXIT_S`` with no byte
from a client. Its interpreter always dies with it (SIGKILL from the kernel if it dies hard).
"""

import argparse
import os
import select
import signal
import subprocess
import sys
import time
from pathlib import Path

from host.core import interpreter, shimcache
from host.core.children import popen_options
from host.core.errors import HarnessError, LinkTimeout
from host.core.paths import REPO
from host.link import Channel, FdTransport, PtyPair
from host.link import frames as F
from host.rig import Rig, RigSpec
from host.rig.targets.firmware import Firmware
from host.rig.targets.target import UnixPortTarget

VREPL_DIR = Path(__file__).resolve().parent / "vrepl"
VBOARD_ROOT = REPO / "build" / "vboard"
SOFT_RESET_RAW, SOFT_RESET_FRIENDLY, HARD_RESET = 10, 11, 12
PROMPTS = (b">>> ", b"... ", b"=== ", b"\r\n>", b"\x04>")
"""Output endings after which the board REPL waits for input."""
STARTUP_S = 0.2
"""Ctrl-C waits this long after a (re)start, as a board ignores it during its C start-up
(the interpreter has no SIGINT handler until ``_vrepl`` installs one)."""
START_TIMEOUT_S = 10.0
IDLE_EXIT_S = 1800.0
"""A detached server (``vboard start``) ends after this long with no byte from a client."""
STOP_S = 5.0
"""A server asked to stop (SIGTERM, SIGHUP, SIGINT) that has not ended by then is ended by
SIGALRM (its interpreter with it)."""


def board_home(board: str) -> Path:
    return VBOARD_ROOT / board


class _Console:
    """The pty pair a board's USB serial is: the client side and the interpreter side,
    and the bridge between them."""

    def __init__(self):
        self.client = PtyPair()  # tools open client.slave_path
        self.repl = PtyPair(console=True)  # the interpreter's stdin/stdout
        self.interrupt = None  # called for a Ctrl-C that is no data (SIGINT to the interpreter)
        self.log = None  # called with a line for the board's log (vboard.log): what the console did
        self.client_t = time.monotonic()  # when a client last wrote (a detached server's idle time)
        self.reset()

    def reset(self) -> None:
        """A new interpreter: no session, no prompt yet."""
        self.link_session = False  # a plant link runs over the console: Ctrl-C is data
        self.prompt = False  # the REPL waits for input: Ctrl-C is data it handles
        self.tail = b""  # the interpreter's last bytes: a prompt may be split across reads
        self.frames = F.Decoder()  # watches the interpreter's output for HELLO and EXIT

    def from_client(self, data: bytes) -> None:
        """Ctrl-C: a byte for the REPL while it waits at a prompt; SIGINT to the
        interpreter while code runs (and never during a plant-link session)."""
        self.client_t = time.monotonic()
        if self.link_session or self.prompt or b"\x03" not in data:
            _write(self.repl.master_fd, data)
            return
        before, _, after = data.partition(b"\x03")
        _write(self.repl.master_fd, before)
        self.say("Ctrl-C from the port while code runs: SIGINT to the interpreter")
        if self.interrupt is not None:
            self.interrupt()
        if after:
            self.from_client(after)

    def from_interpreter(self, data: bytes) -> None:
        # a plant link starts with a HELLO frame and ends with an EXIT frame on the console
        # (whole frames, CRC checked: their bytes may sit anywhere in other frames)
        self.frames.feed(data)
        while (frame := self.frames.next()) is not None:
            if frame[0] in (F.HELLO, F.EXIT):
                self.link_session = frame[0] == F.HELLO
                self.say(f"plant-link session {'begins (Ctrl-C is data)' if self.link_session else 'ends'}")
        seen = self.tail + data  # (the pty may hand over one write in two reads)
        self.prompt = seen.endswith(PROMPTS)
        self.tail = seen[-3:]
        _write(self.client.master_fd, data)

    def say(self, text: str) -> None:
        if self.log is not None:
            self.log(text)

    def close(self) -> None:
        self.client.close()
        self.repl.close()


def _write(fd: int, data: bytes) -> None:
    view = memoryview(data)
    while view:
        try:
            view = view[os.write(fd, view) :]
        except BlockingIOError:
            select.select([], [fd], [], 0.05)
        except OSError:
            return  # nobody on the other end: a board's output goes nowhere too


class VirtualBoardTarget(UnixPortTarget):
    """The board REPL process (``_vrepl``) on the console pty, in the board folder. Wired,
    its ``machine`` and ``time`` are the shim and the link is a pty of its own. A unix-port
    target in all but how it starts, restarts and goes quiet: ending it is the same."""

    board_fs = False  # (its folder is the board's flash already, kept between runs)

    def __init__(self, board: str, fs: Path, wired: bool):
        super().__init__()
        self.board = board
        self.fs = fs
        self.console: _Console | None = None  # given by the virtual board at each start
        self.wired = wired
        self.boot_mode = "friendly"
        self._started_at = 0.0

    def launch(self, firmware) -> None:
        env = {
            "PATH": os.environ.get("PATH", "/usr/bin:/bin"),
            "HIL_REPL_MODE": self.boot_mode,
            "HIL_BOARD_NAME": self.board,
        }
        program = interpreter.find()
        shim = shimcache.folder(program) if self.wired else False  # (compiled once: host/core/shimcache.py)
        if self.wired:
            env.update(firmware.env(self.pty.slave_path, shim))
        env["MICROPYPATH"] = ":".join([str(VREPL_DIR), firmware.micropypath(shim)])
        slave = self.console.repl.slave_fd
        self._started_at = time.monotonic()
        self.proc = subprocess.Popen(
            [str(program), "-m", "_vrepl"],
            env=env,
            cwd=str(self.fs),
            stdin=slave,
            stdout=slave,
            stderr=slave,
            **popen_options(),  # SIGKILL when the server ends, however it ends
        )

    def open(self, firmware, on_console) -> Channel:
        if self.pty is None:
            self.pty = PtyPair()
        else:  # a restart: what the host sent the interpreter before is not for this one
            self.pty.discard()
        self.launch(firmware)
        transport = FdTransport(self.pty.master_fd)
        transport.watch(self.console.repl.master_fd, self.console.from_interpreter)
        transport.watch(self.console.client.master_fd, self.console.from_client)
        return Channel(transport)

    def ended(self) -> int | None:
        """The interpreter's exit code once it ended (a soft reset ends it too)."""
        return self.proc.poll() if self.proc is not None else None

    def reboot(self) -> None:
        """After the interpreter ended: boot again in raw or friendly REPL, as the reset asked."""
        proc, self.proc = self.proc, None
        code = proc.wait(timeout=5) if proc is not None else None
        if code not in (SOFT_RESET_RAW, SOFT_RESET_FRIENDLY, HARD_RESET):
            time.sleep(0.5)  # a crash, not a reset: do not spin
        self.boot_mode = "raw" if code == SOFT_RESET_RAW else "friendly"
        what = {SOFT_RESET_RAW: "soft reset", SOFT_RESET_FRIENDLY: "soft reset", HARD_RESET: "reset"}.get(code, "ended")
        self.console.say(f"the interpreter {what} (exit code {code}): it boots to the {self.boot_mode} REPL")
        self.console.reset()

    def restart(self, firmware, on_console) -> Channel:
        self.reboot()
        return self.open(firmware, on_console)

    def interrupt(self) -> None:
        if self.proc is not None and self.proc.poll() is None:
            early = self._started_at + STARTUP_S - time.monotonic()
            if early > 0:
                time.sleep(early)
            os.kill(self.proc.pid, signal.SIGINT)

    def on_silence(self, rig, timeout_s: float, what: str):
        raise LinkTimeout(f"no {what}")


class VirtualBoard:
    """A board REPL on a pty, in a board folder; wired to a real-time plant or bare."""

    def __init__(
        self,
        board: str = "esp32_devkitc",
        *,
        home: Path | None = None,
        app: str = "rover",
        wired: bool = True,
        seed: int = 0,
    ):
        self.board = board
        self.home = Path(home) if home else board_home(board)
        self.fs = self.home / "fs"
        self.fs.mkdir(parents=True, exist_ok=True)
        self.wired = wired
        self.console_pty = None  # the USB serial: made at start()
        self.target = VirtualBoardTarget(board, self.fs, wired)
        self.firmware = Firmware.flashed(self.fs, require_main=False)  # a fresh board has no main.py
        self.rig = None
        if wired:
            spec = RigSpec(
                app, board=board, seed=seed, mode="realtime", firmware_dir=self.fs, require_main=False, watchdog_s=30.0
            )
            self.rig = Rig(spec, target=self.target)
        self._stopping = False
        self.idle_exit_s = 0.0  # > 0: stop after this long with no byte from a client

    @property
    def port(self) -> str:
        return self.console_pty.client.slave_path

    def start(self) -> "VirtualBoard":
        self._stopping = False
        self.console_pty = self.target.console = _Console()
        self.console_pty.interrupt = self.target.interrupt
        try:
            if self.rig is not None:
                self.rig.start()
            else:
                self.target.launch(self.firmware)
        except BaseException:
            self.stop()
            raise
        return self

    def stop(self) -> None:
        self._stopping = True
        if self.rig is not None:
            self.rig.stop()
        self.target.close()
        if self.console_pty is not None:
            self.console_pty.close()
            self.console_pty = self.target.console = None

    def serve_forever(self, ready=None) -> None:
        """Pump bytes, serve the plant in real time, reboot on resets, until stopped."""
        if ready:
            ready(self.port)
        rig = self.rig
        while not self._stopping and not self._idle():
            if self.target.ended() is not None:
                if rig is not None:
                    rig.restart()
                else:
                    self.target.reboot()
                    self.target.launch(self.firmware)
                continue
            if rig is None:
                self._pump_bare(0.1)
                continue
            if rig.waiting:
                rig.serve_wait(rig.pacing.now_us())
            message = rig.receive(0.005 if rig.waiting else 0.05)
            if message is not None:
                rig.dispatch(*message)

    def _idle(self) -> bool:
        return self.idle_exit_s > 0 and time.monotonic() - self.console_pty.client_t > self.idle_exit_s

    def _pump_bare(self, timeout_s: float) -> None:
        con = self.console_pty
        fds = [con.client.master_fd, con.repl.master_fd]
        ready, _, _ = select.select(fds, [], [], timeout_s)
        for fd in ready:
            try:
                data = os.read(fd, 65536)
            except OSError:
                continue
            if data and fd == con.client.master_fd:
                con.from_client(data)
            elif data:
                con.from_interpreter(data)


# -- command line: one virtual board per board folder, as a background process ---------


def _home(board: str, home: Path | None) -> Path:
    return Path(home) if home else board_home(board)


def running_port(board: str, home: Path | None = None) -> str | None:
    """The port of the running virtual board in this home folder, if one runs."""
    home = _home(board, home)
    try:
        pid = int((home / "vboard.pid").read_text())
        os.kill(pid, 0)
        return (home / "port").read_text().strip()
    except (OSError, ValueError):
        return None


def start_background(
    board: str,
    *,
    home: Path | None = None,
    wired: bool = True,
    app: str = "rover",
    detached: bool = False,
    idle_exit_s: float = IDLE_EXIT_S,
) -> str:
    """Start a virtual board process (if none runs in that folder) and return its port.

    The server is this process's: it gets SIGTERM when the thread that called this ends
    (call it from the main thread, or one that lives as long as the board should), and
    stops with its interpreter. ``detached`` (``vboard start``): it outlives this process
    and ends at ``vboard stop`` or after ``idle_exit_s`` with no client writing to it."""
    port = running_port(board, home)
    if port:
        return port
    home = _home(board, home)
    home.mkdir(parents=True, exist_ok=True)
    portfile = home / "port"
    portfile.unlink(missing_ok=True)
    log = open(home / "vboard.log", "w")
    cmd = [sys.executable, "-m", f"{__package__}.vboard", "serve", "--board", board, "--app", app, "--home", str(home)]
    if not wired:
        cmd.append("--bare")
    if detached:
        cmd += ["--idle-exit-s", f"{idle_exit_s:g}"]
    owner = {"start_new_session": True} if detached else popen_options(signal.SIGTERM)
    proc = subprocess.Popen(cmd, cwd=str(REPO), stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT, **owner)
    log.close()
    deadline = time.monotonic() + START_TIMEOUT_S
    while time.monotonic() < deadline:
        if portfile.exists():
            return portfile.read_text().strip()
        if proc.poll() is not None:
            break
        time.sleep(0.02)
    ended = proc.poll() is not None
    proc.kill()
    proc.wait()
    if ended:  # it stopped by itself: its last line says why
        lines = [line for line in (home / "vboard.log").read_text(errors="replace").splitlines() if line.strip()]
        cause = lines[-1].split(": ", 1)[-1] if lines else "no output"
        raise HarnessError(f"virtual board {board} stopped as it started: {cause}; log: {home / 'vboard.log'}")
    raise HarnessError(f"virtual board {board} did not start within {START_TIMEOUT_S:g} s; log: {home / 'vboard.log'}")


def stop_background(board: str, home: Path | None = None) -> bool:
    try:
        pid = int((_home(board, home) / "vboard.pid").read_text())
    except (OSError, ValueError):
        return False
    try:
        os.kill(pid, signal.SIGTERM)
    except ProcessLookupError:
        return False
    deadline = time.monotonic() + STOP_S + 1  # (its own alarm ends it after STOP_S: that first)
    while time.monotonic() < deadline:
        if _gone(pid):
            return True
        time.sleep(0.02)
    os.kill(pid, signal.SIGKILL)  # (not ended in 5 s, a loaded machine: waited for, reaped when ours)
    deadline = time.monotonic() + 5
    while not _gone(pid) and time.monotonic() < deadline:
        time.sleep(0.02)
    return True


def _gone(pid: int) -> bool:
    """True once the process has ended: reaped here when this process started it (a
    child that ended stays a zombie, alive to kill(pid, 0), until its parent reaps it)."""
    try:
        if os.waitpid(pid, os.WNOHANG)[0] == pid:
            return True
    except ChildProcessError:  # another process's child (a board started by make flash)
        pass
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    return False


def _serve(args) -> int:
    vb = VirtualBoard(args.board, home=args.home, app=args.app, wired=not args.bare, seed=args.seed)
    vb.idle_exit_s = args.idle_exit_s or 0.0

    def on_term(*_):  # (SIGTERM too when the command that owns this server ends)
        vb._stopping = True
        signal.alarm(int(STOP_S))  # not ended by then (stuck, or asked while starting): SIGALRM ends it

    for sig in (signal.SIGTERM, signal.SIGINT, signal.SIGHUP):
        signal.signal(sig, on_term)
    pidfile, portfile = vb.home / "vboard.pid", vb.home / "port"
    try:
        vb.start()
        pidfile.write_text(str(os.getpid()))
        started = time.monotonic()
        vb.console_pty.log = lambda text: print(f"[{time.monotonic() - started:10.3f} s] {text}", flush=True)

        def ready(port):
            partial = portfile.with_suffix(".partial")  # readers never see a half-written name
            partial.write_text(port + "\n")
            os.replace(partial, portfile)
            print(f"virtual board {args.board} on {port} (folder {vb.fs})", flush=True)

        vb.serve_forever(ready)
    finally:
        vb.stop()
        portfile.unlink(missing_ok=True)
        pidfile.unlink(missing_ok=True)
    return 0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m host.device.vboard", description="virtual board on a pty")
    parser.add_argument("command", choices=["start", "stop", "port", "serve"])
    parser.add_argument("--board", default="esp32_devkitc", help="board name (firmware/boards/<board>)")
    parser.add_argument("--app", default="rover", help="app whose plant a wired board drives")
    parser.add_argument("--bare", action="store_true", help="no plant: the unix port's own machine module")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--home", type=Path, help="board folder (default build/vboard/<board>); files in <home>/fs")
    parser.add_argument(
        "--idle-exit-s",
        type=float,
        help=f"end after this many seconds with no byte from a client (start: {IDLE_EXIT_S:g} unless said; "
        "serve: never unless said; 0: never)",
    )
    args = parser.parse_args(argv)
    if args.command == "serve":
        return _serve(args)
    if args.command == "start":
        idle_s = IDLE_EXIT_S if args.idle_exit_s is None else args.idle_exit_s
        print(
            start_background(
                args.board, home=args.home, wired=not args.bare, app=args.app, detached=True, idle_exit_s=idle_s
            )
        )
    elif args.command == "stop":
        print("stopped" if stop_background(args.board, args.home) else "not running")
    else:
        port = running_port(args.board, args.home)
        if not port:
            print(f"error: no virtual board running for {args.board}", file=sys.stderr)
            return 1
        print(port)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
