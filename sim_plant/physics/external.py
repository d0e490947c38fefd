"""The program behind an ``external`` part (``docs/external.md``) and the pins and UART line
it serves on the plant's timeline.

:class:`Program` is the process: JSON lines on its standard input and output, one answer a
request, each within ``timeout_s`` wall seconds; its first request is always ``reset``.

:class:`ExternalLines` is the engine part of the program's pins and UART. The rig tells the
program what is *final* at the instant it happens: the levels of the board outputs wired to
it (``pins``), the bytes the firmware writes, each stamped with the instant its stop bit ends
(``uart``), and the I2C transfers (the chip's ops). Each answer may carry the program's
**plan**: the changes of its pins and the bytes it sends, each at an instant after the
request's. The plant plays the plan at those instants, exactly, and its next change (the
firmware's horizon, the plant's lookahead) is the plan's next instant. A plan with no end (a
clock, a sentence every second) gives ``until_us``: at that instant the rig asks ``more``. A
``more`` is a question, not news: the rig asks it as it looks ahead of the firmware and may
forget the answer (a rewind, ``docs/clock.md``), then tell news from an earlier instant and
ask again; so the program answers ``more`` from what it was told, never from having been
asked. The same ``more`` with no news between is answered from the answer kept.

State (the plan, the levels, the line) is plain data the plant's snapshot copies; the
program (``_SERVERS[key]``) stays out of it: it is never asked to take anything back, since
the rig tells it only what a rewind never goes behind."""

import collections
import json
import os
import select
import subprocess
import tempfile
import time

from sim_plant.engine import Part
from sim_plant.plant import NEVER_US, Change

BITS_PER_BYTE = 10  # start, 8 data, stop
ASKED_MAX = 256  # ``more`` answers kept (a rewind asks again at most one batch back)
STDERR_TAIL = 600  # bytes of the program's stderr an error shows

_SERVERS: dict = {}  # an external part's key -> its Program (kept out of the plant's state)


class ExternalError(RuntimeError):
    """The program did not answer as the protocol says: the message names the part (and
    its rig file), the program and the request, and what came (or did not)."""


class Program:
    """The part's program, started at its first use (``reset`` its first line)."""

    def __init__(self, label: str, command: str | None, timeout_s: float, reset: dict):
        self.label, self.command, self.timeout_s = label, command, timeout_s
        self.reset = reset  # the first request (its levels at reset)
        self.proc = None
        self.stderr = None
        self.reset_answer: dict | None = None
        self.asked: collections.OrderedDict = collections.OrderedDict()  # more's t_us -> its answer

    def begin(self) -> dict:
        """The answer to ``reset`` (the program started if it is not)."""
        if self.proc is None:
            self._start()
        return self.reset_answer

    def ask(self, request: dict) -> dict:
        """News (never taken back): its answer. The ``more`` answers kept are forgotten (the plan may change)."""
        self.begin()
        self.asked.clear()
        return self._ask(request)

    def more(self, t_us: int) -> dict:
        """The plan past ``t_us`` (a question: asked once, however often the rig passes there
        with no news between)."""
        self.begin()
        answer = self.asked.get(t_us)
        if answer is None:
            answer = self.asked[t_us] = self._ask({"t_us": t_us, "op": "more"})
            if len(self.asked) > ASKED_MAX:
                self.asked.popitem(last=False)
        return answer

    def _start(self) -> None:
        if self.command is None:
            raise ExternalError(f"{self.label}: no program to serve it (its command option)")
        self.stderr = tempfile.TemporaryFile()  # (unnamed: nothing left on disk)
        try:
            self.proc = subprocess.Popen(
                [self.command],
                stdin=subprocess.PIPE,
                stdout=subprocess.PIPE,
                stderr=self.stderr,
                cwd=os.path.dirname(self.command),
            )
        except OSError as e:
            self.stderr.close()
            raise ExternalError(f"{self.label}: cannot start {self.command}: {e.strerror or e}") from None
        self.reset_answer = self._ask(self.reset)

    def _ask(self, request: dict) -> dict:
        try:
            self.proc.stdin.write((json.dumps(request) + "\n").encode())
            self.proc.stdin.flush()
        except OSError:
            ended = self._ended()
            raise ExternalError(f"{self.label}: its program {self.command} {ended} before {_asked(request)}") from None
        return self._answer(request)

    def _answer(self, request: dict) -> dict:
        out = self.proc.stdout
        deadline = time.monotonic() + self.timeout_s
        while not select.select([out], [], [], max(0.0, deadline - time.monotonic()))[0]:
            if time.monotonic() >= deadline:
                raise ExternalError(
                    f"{self.label}: its program {self.command} gave no answer to {_asked(request)[3:]} "
                    f"within {self.timeout_s:g} wall s"
                )
        line = out.readline()
        if not line:
            raise ExternalError(
                f"{self.label}: its program {self.command} {self._ended()} before answering {_asked(request)[3:]}"
            )
        try:
            answer = json.loads(line)
        except ValueError:
            answer = None
        if not isinstance(answer, dict):
            got = line.decode(errors="replace").strip()[:200]
            raise ExternalError(
                f"{self.label}: expected one JSON object a line from {self.command} for {_asked(request)[3:]}, "
                f"got {got!r}"
            )
        return answer

    def _ended(self) -> str:
        """``ended (exit status 3); its stderr ends: ...`` (it is waited for a second)."""
        try:
            code = self.proc.wait(timeout=1)
        except subprocess.TimeoutExpired:
            return "closed its output"
        said = ""
        if self.stderr is not None:
            self.stderr.seek(0, os.SEEK_END)
            self.stderr.seek(max(0, self.stderr.tell() - STDERR_TAIL))
            tail = self.stderr.read().decode(errors="replace").strip()
            said = f" (its stderr ends: {tail})" if tail else " (nothing on its stderr)"
        return f"ended with exit status {code}{said}"

    def error(self, what: str, request: dict) -> ExternalError:
        """An answer out of protocol, for ``request``: the error naming the part and the program."""
        return ExternalError(f"{self.label}: {what}, from {self.command} for {_asked(request)[3:]}"[:600])

    def close(self) -> None:
        proc, self.proc = self.proc, None
        if proc is not None:
            try:
                proc.stdin.close()
            except OSError:
                pass  # (it had gone: its pipe broke)
            try:
                proc.wait(timeout=1)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()
            proc.stdout.close()
        if self.stderr is not None:
            self.stderr.close()
            self.stderr = None


def _asked(request: dict) -> str:
    text = json.dumps(request)
    return f"to {text if len(text) <= 200 else text[:197] + '...'}"


def close(key: int) -> None:
    program = _SERVERS.pop(key, None)
    if program is not None:
        program.close()


class ExternalLines(Part):
    """The part's pins (``<name>.<pin>``) and UART line (``<name>.uart``) on the plant's
    timeline, played from its program's plan (the module's doc)."""

    FIXED_STATE = ("inputs", "outputs", "key", "label", "prefix", "uart_signal")

    def __init__(self, name: str, key: int, pins_in, pins_out: dict, uart: bool, baud: int):
        self.label, self.key, self.prefix = name, key, f"{name}."
        self.uart_signal = f"{name}.uart" if uart else None
        self.inputs = {f"{name}.{pin}": "level" for pin in pins_in}
        self.outputs = {f"{name}.{pin}": "level" for pin in pins_out}
        if uart:
            self.inputs[self.uart_signal] = "uart"
            self.outputs[self.uart_signal] = "bytes"
        self.byte_us = BITS_PER_BYTE * 1e6 / baud
        self.levels_in = dict.fromkeys(pins_in, 0)
        self.levels_out = dict(pins_out)
        self.plan: list = []  # (t_us, seq, pin, level), in time order
        self.sends: list = []  # (t_us asked, seq, bytes): what the program sends, in the order asked
        self.sent = 0  # bytes of sends[0] arrived
        self.line_free_us = 0  # when the last byte sent before sends[0] arrived
        self.tx_free_us = 0  # when the firmware's last byte to the program ends
        self.until_us = NEVER_US  # when to ask ``more``
        self.seq = 0
        self.begun = False
        self.next_us = 0  # (the program's reset answer is the plan from 0)

    @property
    def program(self) -> Program:
        return _SERVERS[self.key]

    def close(self) -> None:
        """The program's input closes and it ends (the plant is done with it)."""
        program = _SERVERS.get(self.key)
        if program is not None:
            program.close()

    def initial_outputs(self) -> dict:
        values = {self.prefix + pin: level for pin, level in self.levels_out.items()}
        if self.uart_signal:
            values[self.uart_signal] = b""
        return values

    def begin(self) -> None:
        """The program's plan from its reset (once: the program keeps its answer)."""
        if not self.begun:
            self.begun = True
            self.take({"t_us": 0, "op": "reset"}, self.program.begin())

    def set_input(self, name: str, value, t_us: int, plant) -> bool:
        pin = name[len(self.prefix) :]
        level = 1 if value else 0
        if self.levels_in.get(pin, level) != level:
            self.begin()
            self.levels_in[pin] = level
            request = {"t_us": t_us, "op": "pins", "levels": dict(self.levels_in)}
            self.take(request, self.program.ask(request))
        return False

    def send_bytes(self, name: str, data: bytes, baud: int, t_us: int) -> None:
        """The firmware's bytes on the line at ``baud``, from ``t_us`` (after what it sent before)."""
        self.begin()
        byte_us = BITS_PER_BYTE * 1e6 / max(1, baud)
        start = max(t_us, self.tx_free_us)
        stamped = [[start + round((i + 1) * byte_us), b] for i, b in enumerate(data)]
        self.tx_free_us = start + round(len(data) * byte_us)
        request = {"t_us": t_us, "op": "uart", "baud": baud, "bytes": stamped}
        self.take(request, self.program.ask(request))

    def fire(self, t_us: int, plant, out: list) -> None:
        self.begin()
        plan = self.plan
        while plan and plan[0][0] <= t_us:
            _, _, pin, level = plan.pop(0)
            if self.levels_out[pin] != level:
                self.levels_out[pin] = level
                out.append(Change(t_us, self.prefix + pin, level))
        while self._next_byte_us() <= t_us:
            data = self.sends[0][2]
            out.append(Change(t_us, self.uart_signal, data[self.sent : self.sent + 1]))
            self.sent += 1
            if self.sent == len(data):
                self.sends.pop(0)
                self.sent, self.line_free_us = 0, t_us
        if self.until_us <= t_us:
            self.until_us = NEVER_US
            self.take({"t_us": t_us, "op": "more"}, self.program.more(t_us))
        self._planned()

    def _next_byte_us(self) -> int:
        if not self.sends:
            return NEVER_US
        start = max(self.sends[0][0], self.line_free_us)
        return start + round((self.sent + 1) * self.byte_us)

    def _planned(self) -> None:
        first = self.plan[0][0] if self.plan else NEVER_US
        self.next_us = min(first, self._next_byte_us(), self.until_us)

    def take(self, request: dict, answer: dict) -> None:
        """The plan in ``answer`` (to ``request``, at its instant) over the one before."""
        t_us = request["t_us"]
        if "pins" in answer:
            self._plan_pins(request, t_us, answer["pins"])
        if "uart" in answer:
            self._plan_sends(request, t_us, answer["uart"])
        if "until_us" in answer:
            until = answer["until_us"]
            if until is not None and (not _whole(until) or until <= t_us):
                raise self.program.error(f"expected until_us after {t_us} (or null), got {until!r}", request)
            self.until_us = NEVER_US if until is None else until
        self._planned()

    def _plan_pins(self, request: dict, t_us: int, changes) -> None:
        """Each pin's changes take the place of those planned for it from the first of them on."""
        if not isinstance(changes, list):
            raise self.program.error(f"expected pins: [[t_us, pin, level], ...], got {changes!r}", request)
        given: dict = {}
        seen = set()
        for change in changes:
            if not (isinstance(change, list) and len(change) == 3 and isinstance(change[1], str) and _bit(change[2])):
                raise self.program.error(f"expected [t_us, pin, 0 or 1] in pins, got {change!r}", request)
            t, pin, level = change
            if pin not in self.levels_out:
                known = ", ".join(self.levels_out) or "none"
                raise self.program.error(f"expected one of its pins_out ({known}), got {pin!r}", request)
            if not _whole(t) or t <= t_us:
                raise self.program.error(f"expected instants after {t_us} (the request's), got {t!r}", request)
            if (t, pin) in seen:
                raise self.program.error(f"expected one change of {pin} at {t} us, got two", request)
            seen.add((t, pin))
            given.setdefault(pin, []).append((t, pin, int(level)))
        for pin, planned in given.items():
            first = min(t for t, _, _ in planned)
            self.plan = [c for c in self.plan if c[2] != pin or c[0] < first]
            for t, _, level in planned:
                self.seq += 1
                self.plan.append((t, self.seq, pin, level))
        self.plan.sort()

    def _plan_sends(self, request: dict, t_us: int, sends) -> None:
        """Bytes the program sends: each send on the line from its instant, after what is on it."""
        if self.uart_signal is None:
            raise self.program.error("expected no uart (the part has none: its uart option)", request)
        if not isinstance(sends, list):
            raise self.program.error(f"expected uart: [[t_us, data], ...], got {sends!r}", request)
        for send in sends:
            data = _data(send[1]) if isinstance(send, list) and len(send) == 2 else None
            if data is None:
                what = "[t_us, a list of bytes 0..255 or a text of characters up to U+00FF]"
                raise self.program.error(f"expected {what} in uart, got {send!r}", request)
            if not _whole(send[0]) or send[0] < t_us:
                raise self.program.error(f"expected instants from {t_us} (the request's) on, got {send[0]!r}", request)
            if data:
                self.seq += 1
                self.sends.append((send[0], self.seq, data))
        head = self.sends[:1] if self.sent else []  # (a send under way stays first)
        self.sends = head + sorted(self.sends[len(head) :])


def _bit(value) -> bool:
    return value in (0, 1) and not isinstance(value, bool)


def _whole(value) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and 0 <= value < NEVER_US


def _data(value) -> bytes | None:
    if isinstance(value, str):
        try:
            return value.encode("latin-1")
        except UnicodeEncodeError:
            return None
    if isinstance(value, list) and all(isinstance(b, int) and not isinstance(b, bool) and 0 <= b <= 255 for b in value):
        return bytes(value)
    return None
