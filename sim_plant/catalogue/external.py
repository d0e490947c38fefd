"""Part ``external``: a chip on I2C served by a program outside the rig, in any language
(``docs/external.md``). The rig starts ``command`` (a file relative to the rig file, run as
it is: its ``#!`` line says what runs it) at the firmware's first transfer to the chip and,
for each step of each transfer, writes one JSON line on its standard input, stamped with
the virtual instant, and reads its one-line answer on its standard output before the
firmware's transfer goes on: in lockstep, whatever the program's own speed.

    {"t_us": 1500, "op": "start", "read": false}   ->  {}
    {"t_us": 1500, "op": "write", "byte": 15}      ->  {"ack": true}
    {"t_us": 1500, "op": "read"}                   ->  {"byte": 104}
    {"t_us": 1500, "op": "stop"}                   ->  {}

The program ends when its standard input closes (the rig stops: ``Plant.close``). Its state is its own: the
host never rewinds the plant past a bus transfer (a transfer happens at the firmware's
instant, which a rewind never goes behind), so nothing of it needs taking back."""

import itertools
import json
import os
import select
import subprocess
import time
import weakref

from sim_plant.buses import BusDevice, BusName, check_placement
from sim_plant.catalogue.base import Build, Opt, PartType
from sim_plant.option_table import FileName, Num

_SERVERS: dict = {}  # a chip's key -> its program (kept out of the plant's state: snapshots never copy it)
_KEYS = itertools.count(1)


class ExternalError(RuntimeError):
    """The chip's program did not answer as the protocol says: the message names the part,
    the program and what came (or did not)."""


class _Program:
    """The chip's program, started at its first use; each request answered in one line."""

    def __init__(self, label: str, command: str | None, timeout_s: float):
        self.label, self.command, self.timeout_s = label, command, timeout_s
        self.proc = None

    def ask(self, request: dict) -> dict:
        if self.proc is None:
            self._start()
        line = json.dumps(request) + "\n"
        try:
            self.proc.stdin.write(line.encode())
            self.proc.stdin.flush()
        except OSError as e:
            raise ExternalError(f"{self.label}: its program {self.command} has gone ({e.strerror or e})") from None
        return self._answer(request)

    def _start(self) -> None:
        if self.command is None:
            raise ExternalError(f"{self.label} (external): no command to serve the chip (its command option)")
        try:
            self.proc = subprocess.Popen(
                [self.command], stdin=subprocess.PIPE, stdout=subprocess.PIPE, cwd=os.path.dirname(self.command)
            )
        except OSError as e:
            raise ExternalError(f"{self.label}: cannot start {self.command}: {e.strerror or e}") from None

    def _answer(self, request: dict) -> dict:
        out = self.proc.stdout
        deadline = time.monotonic() + self.timeout_s
        while not select.select([out], [], [], max(0.0, deadline - time.monotonic()))[0]:
            if time.monotonic() >= deadline:
                raise ExternalError(
                    f"{self.label}: its program {self.command} gave no answer to {json.dumps(request)} "
                    f"within {self.timeout_s:g} wall s"
                )
        line = out.readline()
        try:
            answer = json.loads(line)
        except ValueError:
            answer = None
        if not isinstance(answer, dict):
            got = line.decode(errors="replace").strip()[:200] or "nothing (it ended)"
            asked = json.dumps(request)
            raise ExternalError(
                f"{self.label}: expected one JSON object a line from {self.command} for {asked}, got {got}"
            )
        return answer

    def close(self) -> None:
        proc, self.proc = self.proc, None
        if proc is not None:
            proc.stdin.close()
            try:
                proc.wait(timeout=1)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()
            proc.stdout.close()


def _close(key: int) -> None:
    program = _SERVERS.pop(key, None)
    if program is not None:
        program.close()


class ExternalChip(BusDevice):
    """A chip whose every byte its program gives (:class:`_Program`, by ``key``)."""

    FIXED_STATE = (*BusDevice.FIXED_STATE, "key")

    def __init__(self, name: str, bus: str, address: int, command: str | None, timeout_s: float):
        super().__init__(name, bus, address)
        self.key = next(_KEYS)
        _SERVERS[self.key] = _Program(f"{name} ({bus} at 0x{address:02x})", command, timeout_s)
        weakref.finalize(self, _close, self.key)  # (the program ends with the plant, or at exit)

    def _ask(self, request: dict) -> dict:
        return _SERVERS[self.key].ask(request)

    def close(self) -> None:
        """The program's input closes and it ends (it starts again at a later transfer)."""
        program = _SERVERS.get(self.key)
        if program is not None:
            program.close()

    def begin(self, t_us, reading):
        self._ask({"t_us": t_us, "op": "start", "read": reading})

    def write(self, t_us, byte):
        return bool(self._ask({"t_us": t_us, "op": "write", "byte": byte}).get("ack", True))

    def read(self, t_us):
        answer = self._ask({"t_us": t_us, "op": "read"})
        byte = answer.get("byte")
        if not isinstance(byte, int) or not 0 <= byte <= 0xFF:
            raise ExternalError(f"{self.label}: expected {{'byte': 0..255}} for a read, got {answer}"[:300])
        return byte

    def end(self, t_us):
        self._ask({"t_us": t_us, "op": "stop"})


class External(PartType):
    CHIP = None  # (no register file of ours: the program's)
    kind = "external"
    MODELLED_FEATURES = (
        "every byte of every I2C transfer to its address, answered by its program in lockstep (docs/external.md)",
    )
    NOT_MODELLED = ("SPI, pins and UART bytes (I2C only)", "clock stretching: the program's time is not the bus's")
    doc = "A chip on I2C served by a program outside the rig (any language: JSON lines on its stdin and stdout)."
    OPTIONS = (
        Opt("command", FileName(), None, "the program serving the chip, relative to the rig file (run as it is)"),
        Opt("bus", BusName(), "i2c0", "the bus it is on, as the firmware creates it"),
        Opt("address", Num("", 0, 127, whole=True), 0x42, "its 7-bit I2C address"),
        Opt("timeout_s", Num("wall seconds", 0.1, 60), 5.0, "how long an answer may take before the run stops"),
    )
    SIGNALS = ()
    TRUTH = ()
    on_bus = True

    def check(self) -> None:
        check_placement(self.options, "an external chip")

    def add(self, build: Build) -> None:
        o = self.options
        build.parts.append(ExternalChip(self.name, o["bus"], o["address"], o["command"], o["timeout_s"]))
