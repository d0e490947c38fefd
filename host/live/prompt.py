"""``mpy-fil run RIG --interactive``: a run that pauses into a prompt on Ctrl-C, or at a
``--break-at`` instant or console line, offering a live rig's operations (``docs/live.md``,
"In a terminal"), then goes on. The run is served in pieces of :data:`PIECE_US` of virtual
time, so a pause always falls between two of them, at a whole instant. What it shows goes
through ``say``, what it reads through ``ask`` (the command line's): nothing here prints."""

import json
import re
import shlex
import signal

from host.core.errors import HarnessError
from host.live.live import LiveRig

PIECE_US = 10_000  # virtual time served between two looks for a pause (Ctrl-C, the break)
HELP = """commands (times: ms, s simulated; a pause keeps virtual time still):
  c | continue              go on with the run          q | quit     end the run here
  step MS                   run MS ms more              run S        run until t = S s
  until REGEX               run until the console matches
  pin NAME [LEVEL]          run until the pin is at LEVEL (1)
  pins | console [N] | truth | budgets | bus [SINCE_US]             look
  eval EXPR                 a firmware global or attribute       exec LINE    a REPL line in the firmware
  set PART CONTROL VALUE    a part's control            press BUTTON [MS]
  inject JSON               a fault from now on         type TEXT    a line on the console's input
  snapshot | restore N      snapshots"""


class Interactive:
    """A run of ``live`` to ``end_us``, paused on Ctrl-C or at ``break_us`` / a console line
    matching ``break_console``."""

    def __init__(self, live: LiveRig, end_us: int, say, ask, break_us=None, break_console=None):
        self.live = live
        self.end_us = end_us
        self.say = say  # (text) -> None
        self.ask = ask  # (prompt) -> a line, or None at the end of input
        self.break_us = break_us
        self.break_console = re.compile(break_console) if break_console else None
        self.console_from = 0  # console bytes the break looked at already
        self.interrupted = False
        self.snapshots: list = []

    def run(self) -> None:
        """Serve the run to its end, or until the prompt's ``quit``. While it runs, SIGINT
        asks for a pause instead of stopping the command."""
        before = signal.signal(signal.SIGINT, self._interrupt)
        try:
            while self.live.t_us < self.end_us:
                if self._pause_due() and not self.prompt():
                    return
                piece = self.live.t_us + PIECE_US
                if self.break_us is not None and self.break_us > self.live.t_us:
                    piece = min(piece, self.break_us)
                self.live.run_until(t_us=min(piece, self.end_us))
        finally:
            signal.signal(signal.SIGINT, before)

    def _interrupt(self, _signum, _frame) -> None:
        self.interrupted = True

    def _pause_due(self) -> bool:
        why = None
        if self.interrupted:
            why, self.interrupted = "Ctrl-C", False
        elif self.break_us is not None and self.live.t_us >= self.break_us:
            why, self.break_us = f"--break-at {self.break_us / 1e6:g}s", None
        elif self.break_console is not None:
            text, start = self.live.rig.console_log.since(self.console_from)
            found = self.break_console.search(text)
            self.console_from = start + len(text.encode())
            if found:
                why, self.break_console = f"--break-at {self.break_console.pattern!r}: {found.group(0)!r}", None
        if why is not None:
            self.say(f"paused at virtual t={self.live.t_us / 1e6:.6f} s ({why}); `help` lists the commands")
        return why is not None

    def prompt(self) -> bool:
        """Commands until ``continue`` (True) or ``quit`` / the end of input (False)."""
        signal.signal(signal.SIGINT, signal.default_int_handler)  # (Ctrl-C at the prompt: stops it)
        try:
            while True:
                line = self.ask(f"[{self.live.t_us / 1e6:.6f} s] mpy-fil> ")
                if line is None:
                    return False
                words = line.strip().split(None, 1)
                if not words:
                    continue
                verb, rest = words[0], (words[1] if len(words) > 1 else "")
                if verb in ("c", "continue"):
                    return True
                if verb in ("q", "quit", "exit"):
                    return False
                self._command(verb, rest)
        finally:
            signal.signal(signal.SIGINT, self._interrupt)

    def _command(self, verb: str, rest: str) -> None:
        live = self.live
        try:
            shown = self._look(verb, rest) if verb in LOOKS else self._act(verb, rest)
        except (HarnessError, ValueError, AssertionError, KeyError, IndexError) as e:
            shown = f"{type(e).__name__}: {e}"
        if shown is not None:
            self.say(shown if isinstance(shown, str) else _lines(shown))
        if live.rig.exit_kind is not None:
            self.say("the firmware has ended")

    def _look(self, verb: str, rest: str):
        live = self.live
        if verb == "pins":
            return live.pins()
        if verb == "console":
            return live.console(lines=int(rest or 20)).rstrip("\n")
        if verb == "truth":
            return live.truth()
        if verb == "budgets":
            return live.budgets()
        if verb == "bus":
            return live.bus_log(int(rest or 0))
        if verb == "eval":
            return repr(live.eval(rest))
        return HELP

    def _act(self, verb: str, rest: str):
        live, args = self.live, shlex.split(rest) if verb not in ("exec", "until", "inject", "type") else [rest]
        if verb == "exec":
            return live.exec(rest)
        if verb == "step":
            live.step(round(float(args[0]) * 1000))
        elif verb == "run":
            live.run_until(t_s=float(args[0]))
        elif verb == "until":
            return repr(live.run_until(console=rest).group(0))
        elif verb == "pin":
            live.run_until(pin=args[0], level=int(args[1]) if len(args) > 1 else 1)
        elif verb == "set":
            live.set(args[0], args[1], _number(args[2]))
        elif verb == "press":
            live.press(args[0], float(args[1]) if len(args) > 1 else 100)
        elif verb == "inject":
            return live.inject(json.loads(rest))
        elif verb == "type":
            live.uart_write(rest + "\n")
        elif verb == "snapshot":
            self.snapshots.append(live.snapshot())
            return f"snapshot {len(self.snapshots) - 1} at t={live.t_us / 1e6:.6f} s"
        elif verb == "restore":
            live.restore(self.snapshots[int(args[0])])
        else:
            return f"no command {verb!r}\n{HELP}"
        return f"t={live.t_us / 1e6:.6f} s"


LOOKS = ("pins", "console", "truth", "budgets", "bus", "eval", "help", "?")


def _lines(value) -> str:
    """A dict one key a line (a pin, a budget: its fields on one line), a list one item a line."""
    if isinstance(value, dict):
        return "\n".join(f"{key}: {json.dumps(item, default=str)}" for key, item in value.items()) or "(none)"
    if isinstance(value, list):
        return "\n".join(json.dumps(item, default=str) for item in value) or "(none)"
    return json.dumps(value, default=str)


def _number(text: str):
    """A control's value: a number when it reads as one (a slide switch's ``left`` stays text)."""
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text
