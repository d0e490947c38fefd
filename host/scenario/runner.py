"""A Wokwi automation scenario run against a rig, in virtual time.

Each step runs at the rig's virtual instant with Wokwi's meaning
(docs/wokwi-scenarios.md): ``delay`` runs the rig that long; ``wait-serial`` runs it
until a line the firmware prints (ended by its newline, after the step began) contains
the text; ``write-serial`` puts bytes on the board's console input (the firmware's
``sys.stdin``); ``set-control`` sets a part's control (``sim_plant.controls``) at this
instant; ``expect-pin`` checks a pin's level now; ``wait-pin`` (ours) runs until it is.
The whole run's timeout is simulated time, as Wokwi's ``--timeout``: a step that would
run past it fails. A failing step raises :class:`StepFailed` naming the step, its line
and what was seen (the console's last lines, the pin's level) and the artefacts.
"""

import time
from dataclasses import dataclass

from host.core.errors import HarnessError
from host.core.printable import printable
from host.link import frames as F
from host.rig.hardware.wiring import PROBE_PREFIX
from sim_plant.controls import ControlError

ONE_LINE_PINS = {"button": ("1.l", "1.r", "2.l", "2.r"), "slide_switch": ("1", "2", "3"), "probe": ("A", "C")}
ONE_LINE_PINS["buzzer"] = ("1", "2")
"""Wokwi's pin names of a part whose one line the board sees under another name (its
contacts, an LED's anode and cathode: host/rig/config/wokwi/parts.py's mappers); every other pin is
named as its signal (Wokwi's ``TRIG`` is ``<part>.trig``)."""
LOOK_US = 1_000  # simulated time between two looks of a wait (a board's system tick)
TAIL_LINES = 5  # console lines a failure shows


class StepFailed(HarnessError, AssertionError):
    """A scenario's step failed: the message names the step, its line and what was seen."""


@dataclass
class StepResult:
    step: object
    t_us: int  # when it began
    end_us: int  # when it ended
    wall_s: float


class ScenarioRun:
    """One scenario on one started rig; ``echo(line)`` shows each step as it runs."""

    def __init__(self, rig, scenario, echo=None):
        self.rig = rig
        self.scenario = scenario
        self.echo = echo or (lambda line: None)
        self.deadline_us = rig.t_us + scenario.timeout_us
        self.line_from = rig.console_log.total_bytes  # where the console's next unread line starts
        self.results: list[StepResult] = []
        self.previous = None  # the step before this one

    def run(self) -> list[StepResult]:
        for step in self.scenario.steps:
            t0_us, wall0 = self.rig.t_us, time.perf_counter()
            self.echo(printable(f"[{t0_us / 1e6:11.6f} s] line {step.line}: {step.describe()}"))
            try:
                getattr(self, "_" + step.kind.replace("-", "_"))(step)
            except StepFailed:
                raise
            except HarnessError as e:  # (the firmware hung, crashed, ended with an error)
                raise StepFailed(
                    printable(
                        f"{self.scenario.path}:{step.line}: step {step.describe()} failed: {type(e).__name__}: {e}"
                    )
                ) from e
            self.results.append(StepResult(step, t0_us, self.rig.t_us, time.perf_counter() - wall0))
            self.previous = step
        return self.results

    # -- steps ----------------------------------------------------------------------

    def _delay(self, step) -> None:
        t_end = self.rig.t_us + step.args["delay_us"]
        if t_end > self.deadline_us:
            self._run_to(self.deadline_us)
            self._fail(step, "the scenario's timeout came first" + self._timeout_text())
        self._run_to(t_end)

    def _wait_serial(self, step) -> None:
        text = step.args["text"]
        if self.previous is None or self.previous.kind != "wait-serial":  # (wait-serials in a row read on)
            self._skip_to_line_start()
        while True:
            if self._line_with(text):
                return
            if self.rig.t_us >= self.deadline_us or self.rig.exit_kind is not None:
                why = "the firmware ended" if self.rig.exit_kind is not None else "the scenario's timeout came"
                self._fail(step, f"{why} before a line with {text!r}{self._timeout_text()}")
            self._run_to(min(self.deadline_us, self.rig.t_us + LOOK_US))

    def _write_serial(self, step) -> None:
        try:
            write_console(self.rig, step.args["data"])
        except StepFailed as e:
            self._fail(step, str(e))

    def _set_control(self, step) -> None:
        a = step.args
        try:
            self.rig.plant.set_control(a["part"], a["control"], a["value"])
        except ControlError as e:
            self._fail(step, str(e))

    def _expect_pin(self, step) -> None:
        level, what = pin_level(self.rig, step.args["part"], step.args["pin"])
        if level != step.args["value"]:
            self._fail(step, f"{what} is {level}, expected {step.args['value']}")

    def _wait_pin(self, step) -> None:
        a = step.args
        deadline = self.deadline_us
        if "timeout_us" in a:
            deadline = min(deadline, self.rig.t_us + a["timeout_us"])
        while True:
            level, what = pin_level(self.rig, a["part"], a["pin"])
            if level == a["value"]:
                return
            if self.rig.t_us >= deadline:
                whose = "its timeout" if deadline < self.deadline_us else "the scenario's timeout"
                self._fail(step, f"{what} still {level} when {whose} came, expected {a['value']}{self._timeout_text()}")
            self._run_to(min(deadline, self.rig.t_us + LOOK_US))

    # -- helpers --------------------------------------------------------------------

    def _run_to(self, t_us: int) -> None:
        if t_us > self.rig.t_us:
            self.rig.run_until(t_us)

    def _skip_to_line_start(self) -> None:
        """Lines that ended before this step are not looked at: Wokwi's wait-serial looks
        at the lines completed while it waits (wait-serials in a row read the console on,
        line after line, from the last one matched)."""
        text, start = self.rig.console_log.since(self.line_from)
        end = text.rfind("\n")
        if end >= 0:
            self.line_from = start + len(text[: end + 1].encode())

    def _line_with(self, text: str) -> bool:
        got, start = self.rig.console_log.since(self.line_from)
        offset = start
        for line in got.splitlines(keepends=True):
            if not line.endswith("\n"):
                break  # (a line still being printed)
            offset += len(line.encode())
            if text in line.rstrip("\r\n"):
                self.line_from = offset
                return True
        return False

    def _timeout_text(self) -> str:
        return f" (timeout {self.scenario.timeout_us / 1e6:g} simulated s, at t={self.deadline_us / 1e6:g} s)"

    def _fail(self, step, what: str) -> None:
        lines = self.rig.console.rstrip().splitlines()[-TAIL_LINES:]
        seen = "\n  ".join(lines) if lines else "(nothing)"
        artefacts = f"\nartefacts: {self.rig.artefacts}" if self.rig.artefacts else ""
        raise StepFailed(
            printable(
                f"{self.scenario.path}:{step.line}: step {step.describe()} failed at virtual "
                f"t={self.rig.t_us / 1e6:.6f} s: {what}\nlast serial lines:\n  {seen}{artefacts}"
            )
        )


def write_console(rig, data: bytes) -> None:
    """Bytes on the board's console input, at the rig's instant: the firmware reads them
    from ``sys.stdin`` when it next looks (the unix port's stdin)."""
    proc = getattr(rig.target, "proc", None)
    if proc is None or proc.stdin is None or rig.exit_kind is not None:
        raise StepFailed("the firmware is not running (nothing reads the console)")
    try:
        proc.stdin.write(data)
        proc.stdin.flush()
    except OSError as e:
        raise StepFailed(f"the console's input is closed ({e.strerror or e})") from None


def pin_level(rig, part: str, pin: str) -> tuple[int, str]:
    """(the level now, what was read) of Wokwi's ``part-id``/``pin``: a part's signal
    (``<part>.<pin>``, driven by the plant or by the firmware), a probe (``probe:<part>``,
    any pin), or a board pin (its rig name or its number, whatever ``part`` is)."""
    plant = rig.plant
    signal = _signal(rig, part, pin)
    if signal is not None and signal in plant.outputs:
        return int(bool(plant.output(signal))), f"{part}:{pin} ({signal}, driven by the plant)"
    handles = [h for h in rig.wiring.handles if h.kind and _is(h, signal, pin)]
    if not handles:
        return 0, f"{part}:{pin} ({signal or 'pin ' + pin}, never driven by the firmware)"
    handle = handles[-1]
    if handle.kind == F.CFG_PWM:
        return int(bool(handle.level)), f"{part}:{pin} (a PWM output, duty {handle.level})"
    if handle.is_input:
        value = plant.output(handle.signal) if handle.signal in plant.outputs else handle.peripheral.idle(handle)
        return int(bool(value)), f"{part}:{pin} (an input of the firmware's)"
    return int(bool(handle.level)), f"{part}:{pin} ({handle.signal or 'pin ' + handle.key})"


def _signal(rig, part: str, pin: str) -> str | None:
    """The plant signal or probe ``part``/``pin`` names (None: a board pin): the part's
    signal of that name (any case: Wokwi's ``ECHO`` is our ``echo``), else a part's only
    signal (an LED's ``A``, a button's ``1.l``: the one line the board sees), else the
    probe ``probe:<part>``."""
    signals = {**rig.plant.inputs, **rig.plant.outputs}
    wanted = f"{part}.{pin}".lower()
    for name in signals:
        if name.lower() == wanted:
            return name
    own = [name for name in signals if name.startswith(part + ".")]
    if len(own) == 1 and pin.lower() in {p.lower() for p in one_line_pins(rig.plant, part)}:
        return own[0]
    probe = PROBE_PREFIX + part
    if probe in rig.app.wiring.values():
        return probe
    return None


def one_line_pins(plant, part: str) -> tuple:
    """The Wokwi pin names of ``part`` that mean its one line (ONE_LINE_PINS, by its kind)."""
    kind = next((p.kind for p in plant.catalogue_parts if p.name == part), None)
    return ONE_LINE_PINS.get(kind, ())


def part_pins(plant, part: str) -> list[str]:
    """Every pin name ``part`` answers to: its signals' names, and its one line's Wokwi names."""
    own = [name.split(".", 1)[1] for name in {**plant.inputs, **plant.outputs} if name.startswith(part + ".")]
    return own + (list(one_line_pins(plant, part)) if len(own) == 1 else [])


def _is(handle, signal: str | None, pin: str) -> bool:
    if signal is not None:
        return handle.signal == signal
    return pin in (handle.board_name, handle.key) or pin.upper().lstrip("GPD") == handle.key


def known_ids(app, plant) -> set[str]:
    """The part-ids a scenario may name: the plant's parts, the probes, and (any id) a
    board pin of the rig's wiring."""
    parts = {name.split(".", 1)[0] for name in {**plant.inputs, **plant.outputs}}
    probes = {v[len(PROBE_PREFIX) :] for v in app.wiring.values() if v.startswith(PROBE_PREFIX)}
    return parts | probes
