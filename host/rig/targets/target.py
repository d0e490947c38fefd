"""Targets: where the firmware runs, and the byte stream to its shim.

A :class:`~host.rig.loop.rig.Rig` drives every target the same way; each medium implements
this small interface, as mpremote's transports and pySerial's backends implement
theirs. :class:`UnixPortTarget` runs MicroPython's unix port in a child process with the
link on a pty; the board and virtual-board targets live with the devices
(:mod:`host.device.pil`, :mod:`host.device.vboard`).
"""

import os
import re
import signal
import subprocess
import time
from pathlib import Path

from host.core import interpreter, shimcache
from host.core.children import popen_options
from host.core.errors import FirmwareError, FirmwareHung, HarnessError, LinkTimeout, SetupError
from host.core.paths import SHIM_DIR
from host.core.printable import printable
from host.link import Channel, FdTransport, PtyPair
from host.link import frames as F
from host.link.faults import wrap
from host.rig.targets import sandbox

EXIT_WAIT_S = 5.0
COVERAGE_STOP_S = 10.0  # for a traced firmware to save its coverage after BYE (docs/coverage.md)
STACK_WAIT_S = 1.0  # for the traceback of a firmware interrupted where it hung


def end_process(proc: subprocess.Popen) -> None:
    """Kill a firmware process and everything in its session; reap it."""
    if proc.poll() is None:
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    try:
        proc.wait(timeout=EXIT_WAIT_S)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait(timeout=EXIT_WAIT_S)


def _discard(_data: bytes) -> None:
    pass


def _stack(proc, rig) -> str:
    """Where a silent firmware is: SIGINT makes MicroPython raise KeyboardInterrupt in the
    code it runs, and the shim sends that traceback (FAULT). Empty if none comes."""
    try:
        os.kill(sandbox.interpreter_pid(proc), signal.SIGINT)
        deadline = time.monotonic() + STACK_WAIT_S
        while time.monotonic() < deadline:
            # (despite a gap: the frame lost before it is what the counters are for)
            got = rig.session.poll(deadline - time.monotonic(), despite_damage=True)
            if got is not None and got[0] == F.FAULT:
                return F.unpack_fault(got[1])[1].decode(errors="replace")
    except (OSError, HarnessError):
        pass
    return ""


LOSS_COUNTERS = ("seq_gaps", "bad_crc", "bad_length", "truncated")
WAITING_ON_LINK = (" in recv", " in exchange", " in _sync")  # the shim's functions that wait for the host
# (_sync: over the C link, _hilfast.link, its wait is a C call there)


def waiting_on_link(stack: str) -> bool:
    """The interrupted firmware was in the shim, waiting for a frame from the host."""
    frames = [line for line in stack.splitlines() if line.lstrip().startswith("File ")]
    return bool(frames) and "_hil" in frames[-1] and frames[-1].endswith(WAITING_ON_LINK)


SPINS = (
    ". Its innermost frame calls nothing of the board's (no clock or pin read, no sleep). In a hard IRQ's "
    "handler a loop like that moves no virtual time (the handler runs at its edge's instant, and on a board "
    "nothing else runs until it returns), and neither does one anywhere on an interpreter without the "
    "harness's branch hook (HIL_PURE, a user's own MICROPYTHON), so a Timer or an IRQ it waits for "
    "(`while playing: pass`) never comes due, where a board's would interrupt it (docs/mcu-time.md, "
    '"A loop that calls nothing of the board\'s"); a sleep or a clock read in the loop lets it'
)


BRANCH_HOOK = ("_branches", "_spin_told")
"""The shim's functions the VM's branch hook runs inside the firmware's own loop (_hil): a
stack interrupted in them is the firmware's loop's."""


def spins_in_own_code(stack: str) -> bool:
    """The interrupted firmware's innermost frame is its own code, not the shim's (a board's C);
    the branch hook's frames on top of it (BRANCH_HOOK) do not count."""
    frames = re.findall(r'File "([^"]+)", line \d+, in (\S+)', stack)
    while frames and frames[-1][1] in BRANCH_HOOK:
        frames.pop()
    if not frames:
        return False
    folder = Path(frames[-1][0]).parent
    return folder != SHIM_DIR and folder.parent.name != "shim"  # (the shim, or its compiled copy: build/shim/<key>/)


def diagnosis(stack: str, counters: dict, sent_any: bool) -> str:
    """Which way a frame was lost, as the link's counters and the firmware's stack show it."""
    lost = ", ".join(f"{k}={counters[k]}" for k in LOSS_COUNTERS if counters.get(k))
    if lost:
        return (
            f"a frame from the firmware (firmware→host) was lost: the host saw it in the firmware's sequence "
            f"numbers ({lost}), and the firmware waits for the answer to a message the host never got"
        )
    if stack and not waiting_on_link(stack):
        why = "nothing was lost on the link in either direction: the firmware hangs in its own code (its stack below)"
        return why + (SPINS if spins_in_own_code(stack) else "")
    if not sent_any:
        return (
            "nothing has been sent to the firmware yet, so no frame to it was lost; the firmware's first frame "
            "(HELLO, firmware→host) was lost on its way, or the firmware never started its shim"
        )
    if stack:
        return (
            "nothing from the firmware was lost (no gap in its sequence numbers) and it waits in the shim for the "
            "host: a frame to the firmware (host→firmware) was lost on its way"
        )
    return (
        "no stack came back and nothing from the firmware was lost (no gap in its sequence numbers): a frame "
        "lost on its way to the firmware (host→firmware) looks the same"
    )


class Target:
    """The contract. ``open`` starts the firmware and returns the framed channel to its
    shim; ``restart`` does so again after the firmware reset the board; ``close`` ends it
    (safe to call twice); ``on_silence`` raises the error for a firmware that went quiet.
    ``board_fs``: the firmware runs here on a per-run copy of its files (the unix port)."""

    board_fs = False

    def open(self, firmware, on_console) -> Channel:
        raise NotImplementedError

    def restart(self, firmware, on_console) -> Channel:
        raise NotImplementedError

    def power_cycle(self, firmware, on_console) -> Channel:
        """The board loses power where it is and boots again (a brownout)."""
        raise HarnessError(f"{type(self).__name__}: a power cycle is not modelled on this target")

    def alive(self) -> bool:
        """Opened and not closed."""
        raise NotImplementedError

    def shim_settings(self, firmware):
        """What the shim is told in WELCOME (host/rig/targets/firmware.py ShimSettings): a
        firmware run here is told all the rig file sets."""
        return firmware.shim_settings()

    def close(self, session_open: bool = False) -> None:
        """End the firmware; ``session_open``: the shim still waits on the link."""
        raise NotImplementedError

    def on_silence(self, rig, timeout_s: float, what: str):
        """Nothing came within ``timeout_s`` (0: the link failed): stop ``rig`` and raise."""
        raise NotImplementedError


class UnixPortTarget(Target):
    """The unix port in a child process of its own session; its console (stdout and
    stderr) is a pipe watched with the link, so printed text keeps its place. The child
    dies with the thread that started it (:mod:`host.core.children`): start and run a rig
    from one thread that lives as long as the rig."""

    board_fs = True

    def __init__(self, busy_poll_s: float = 0.0):
        self.busy_poll_s = busy_poll_s
        self.proc: subprocess.Popen | None = None
        self.pty: PtyPair | None = None
        self._on_console = None
        self._traced: Channel | None = None  # the channel of a firmware that records coverage

    def open(self, firmware, on_console) -> Channel:
        if self.pty is None:
            self.pty = PtyPair()
        self._on_console = on_console
        tracing = firmware.coverage_fd is not None  # (docs/coverage.md: the settrace variant)
        version = firmware.micropython() if hasattr(firmware, "micropython") else None
        program = str(interpreter.find_variant("settrace" if tracing else "standard", version))
        argv = [program, *firmware.interpreter_args(), "-c", "import _hilboot; _hilboot.main()"]
        setting = sandbox.setting(firmware.sandbox)
        shim = shimcache.folder(program)  # (compiled once: host/core/shimcache.py)
        argv = sandbox.command(argv, firmware.board_root, self.pty.slave_path, setting, firmware.main_dir, shim)
        try:
            self.proc = subprocess.Popen(
                argv,
                env=firmware.env(self.pty.slave_path, shim),
                cwd=str(firmware.board_root or firmware.main_dir),
                stdin=subprocess.PIPE,  # open and empty, as a board's console with no one typing
                stdout=subprocess.PIPE,
                stderr=subprocess.STDOUT,
                pass_fds=(firmware.coverage_fd,) if tracing else (),
                **popen_options(),  # its own session; SIGKILL when the process that runs the rig ends
            )
        except OSError as e:  # not a program this machine runs (no shebang, wrong format)
            raise SetupError(
                f"cannot start the interpreter {program}: {e.strerror or e}; "
                "expected MicroPython's unix port (set MICROPYTHON, or unset it for the build)"
            ) from None
        transport = FdTransport(self.pty.master_fd, busy_poll_s=self.busy_poll_s)
        transport.watch(self.proc.stdout.fileno(), on_console)
        chan = Channel(transport)
        self._traced = chan if tracing else None
        return chan

    def restart(self, firmware, on_console) -> Channel:
        """machine.reset(): the process ends by itself after EXIT; start a new one on
        the same pty (the plant carries on)."""
        proc, self.proc = self.proc, None
        proc.wait(timeout=EXIT_WAIT_S)
        self._drain(proc)
        return self.open(firmware, on_console)

    def power_cycle(self, firmware, on_console) -> Channel:
        """A brownout: the process is killed where it is (blocked in a wait, nothing said)
        and a new one starts on the same pty (the plant carries on)."""
        proc, self.proc = self.proc, None
        if proc is not None:
            end_process(proc)
            self._drain(proc)
        return self.open(firmware, on_console)

    def alive(self) -> bool:
        return self.proc is not None

    def close(self, session_open: bool = False) -> None:
        proc, self.proc = self.proc, None
        traced, self._traced = self._traced, None
        if proc is not None and traced is not None and session_open:
            self._bye(proc, traced)
        if proc is not None:
            end_process(proc)
            self._drain(proc)
        if self.pty is not None:
            self.pty.close()
            self.pty = None

    def _bye(self, proc, chan) -> None:
        """A traced firmware stops as at a board's REPL (BYE; again at each wait it makes
        while it unwinds), so its tracer saves before EXIT. What it prints after BYE is not
        the run's: the console keeps what came before, as when the process is killed."""
        self._drain(proc, close=False)
        self._on_console = None
        side = getattr(chan.transport, "side", {})
        for fd in side:
            side[fd] = _discard
        deadline = time.monotonic() + COVERAGE_STOP_S
        try:
            chan.send(F.BYE, b"")
            while proc.poll() is None and time.monotonic() < deadline:
                try:
                    type_, _seq, _payload = chan.recv_despite_damage(min(0.2, deadline - time.monotonic()))
                except LinkTimeout:
                    continue
                if type_ == F.EXIT:
                    return
                if type_ in (F.WAIT, F.BUS):
                    chan.send(F.BYE, b"")
        except (OSError, HarnessError):
            pass

    def _drain(self, proc, close: bool = True) -> None:
        """The rest of what the process printed, then close its pipe."""
        if proc.stdout is None:
            return
        try:
            os.set_blocking(proc.stdout.fileno(), False)
            rest = proc.stdout.read()
            if rest and self._on_console is not None:
                self._on_console(rest)
        except (OSError, ValueError):
            pass
        if not close:
            return
        proc.stdout.close()
        if proc.stdin is not None:
            proc.stdin.close()

    def on_silence(self, rig, timeout_s: float, what: str):
        proc = self.proc
        if proc is not None and proc.poll() is None and timeout_s > 0:
            last, sent = rig.last_message(), rig.session.last_sent()
            stack = _stack(proc, rig)
            rig.stop()
            counters = rig.session.counters()
            link = ", ".join(f"{k}={v}" for k, v in counters.items() if v)
            why = diagnosis(stack, counters, sent != "nothing")
            where = f"\nwhere it was (interrupted by the watchdog):\n{printable(stack.rstrip())}" if stack else ""
            raise FirmwareHung(
                f"firmware stopped answering: expected {what} within {timeout_s:g} s of wall time, "
                f"got nothing (virtual t={rig.clock.firmware_us / 1e6:.6f} s, last message {last}, "
                f"last sent {sent}; link: {link}); {why}{where}\nthe watchdog stopped it.{rig.where()}"
            )
        code = proc.wait(timeout=EXIT_WAIT_S) if proc is not None else None
        rig.stop()
        raise FirmwareError(
            f"firmware process ended with exit code {code} while the host expected {what} "
            f"(virtual t={rig.clock.firmware_us / 1e6:.6f} s).{rig.where()}",
            console=rig.console,
        )


class FaultyLinkTarget(UnixPortTarget):
    """The unix port, with link faults under each channel it opens (a restart draws
    afresh: each boot has a stream of its own)."""

    def __init__(self, busy_poll_s: float, faults, seed: int):
        super().__init__(busy_poll_s)
        self.faults = faults
        self.seed = seed
        self.boots = 0
        self.transport = None

    def open(self, firmware, on_console):
        chan = wrap(super().open(firmware, on_console), self.faults, (self.seed + 7919 * self.boots) & 0xFFFFFFFF)
        self.boots += 1
        self.transport = chan.transport
        return chan
