"""A failing run's failure signature: what "fails the same way" means when a run is
shrunk (``docs/testing-tools.md``, "Failure signature").

A signature is ``(category, source, message_class)``:

- ``error``: the run ended in a harness error; ``source`` is its class (``FirmwareError``,
  ``FirmwareHung``, ``LinkDamaged``, ``RunTimeout``, ``crash``);
- ``budget``: the judge passed it but budgets the campaign keeps were missed; ``source``
  is ``budgets``, the class names the budgets missed (sorted);
- ``judge``: the judge failed it; ``source`` is the judge's name.

The message class is the message's first line with every number (integer, decimal,
exponent, hexadecimal) written ``#`` and runs of white space as one space: "home 289 mm
off" and "home 227 mm off" are one class, "home off" and "branch not explored" are two.
A firmware that raised (``FirmwareError``) adds the exception's line of MicroPython's
traceback and where it was raised (the innermost ``File "main.py", line 40``, its number
kept): ``firmware raised at virtual t=# s; ... | RuntimeError: battery low: # at # ms @
main.py:40`` (a ``ValueError`` raised at the same instant, or the same exception raised by
another line, is another failure). A passing run has no signature (None).

Some failures a shorter run has whatever the firmware does: a judge's deadline ("within #
s"), or a judge that wants something to happen and it did not (a text on the console, a
floor covered): :attr:`Signature.needs_duration`. A shrink never cuts such a run's
duration (a fixed firmware would fail the cut run the same way). A failure that is the
harness's own (its crash, a setting it refused: :data:`HARNESS_OWN`) is no failure of the
firmware: a shrink refuses it rather than shrink it.
"""

import re
from typing import NamedTuple

NUMBER = re.compile(r"[-+]?(?:0x[0-9a-fA-F]+|(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)")
DEADLINE = re.compile(r"\bwithin # (?:s|simulated min)\b")
"""The judges' wording for "the run ended before it got there" (judges.py)."""
ABSENT = re.compile(r"^expected ['\"].*['\"] on the console|^expected >= # ?% (?:of the floor )?covered\b")
"""The judges' wording for "something that must happen did not" (judges.py: ``declared``'s
``console`` and ``min_coverage``, ``pool_mission``'s coverage): a shorter run fails so too."""
HARNESS_OWN = frozenset(
    {"crash", "ConfigError", "PlantOptionsError", "ScenarioError", "SetupError", "DriverMissing", "TraceWriteError"}
)
"""Errors that are the harness's own, not the firmware's: a shrink refuses such a run."""
WHERE = re.compile(r'^\s*File "([^"]*)", line (\d+)')
CLASS_CHARS = 200
TRACEBACK = "MicroPython traceback:"  # (host.rig: a FirmwareError's message, then the traceback)


class Signature(NamedTuple):
    category: str  # error | budget | judge
    source: str  # the error's class, "budgets", or the judge's name
    message_class: str

    def __str__(self) -> str:
        return f"{self.category} {self.source}: {self.message_class}"

    @property
    def deadline(self) -> bool:
        """The judge failed the run for not getting somewhere within its duration: a
        shorter run fails that way whatever the firmware does, so its duration is kept."""
        return self.category == "judge" and bool(DEADLINE.search(self.message_class))

    @property
    def needs_duration(self) -> bool:
        """A shorter run fails this way whatever the firmware does: a deadline, or
        something the judge wants to happen that did not (:data:`ABSENT`)."""
        parts = self.message_class.split("; ")  # (declared: every condition missed)
        return self.deadline or (self.category == "judge" and any(ABSENT.search(part) for part in parts))

    @property
    def harness_own(self) -> bool:
        """The harness failed (crashed, or refused a setting), not the firmware."""
        return self.category == "error" and self.source in HARNESS_OWN

    def to_dict(self) -> dict:
        return self._asdict()


def message_class(message: str) -> str:
    """The first line, numbers as ``#``, white space collapsed (at most 200 characters)."""
    first = (message or "").strip().splitlines()[0] if (message or "").strip() else ""
    return " ".join(NUMBER.sub("#", first).split())[:CLASS_CHARS]


def firmware_exception(message: str) -> str:
    """The exception's line of the MicroPython traceback in a message, classed; "" without."""
    lines = message.splitlines()
    if TRACEBACK not in lines:
        return ""
    where = ""
    for line in lines[lines.index(TRACEBACK) + 1 :]:
        found = WHERE.match(line)
        if found:
            where = f" @ {found.group(1)}:{found.group(2)}"  # (the innermost frame: the line that raised)
        elif line.strip() and not line.startswith((" ", "\t", "Traceback")):
            return message_class(line) + where
    return ""


def signature(result: dict, judge: str) -> Signature | None:
    """A finished run's signature (``host.campaign.worker.run_one``'s result), or None when
    it passed. ``judge`` is the task's judge."""
    if result.get("passed"):
        return None
    message = result.get("message") or ""
    if result.get("error"):
        text = message.split(": ", 1)[1] if message.startswith(f"{result['error']}: ") else message
        raised = firmware_exception(text)
        return Signature("error", str(result["error"]), message_class(text) + (f" | {raised}" if raised else ""))
    if message.startswith("expected the budgets kept, missed: "):
        names = sorted(re.findall(r"([\w.:-]+) \(\d+ misses\)", message))
        return Signature("budget", "budgets", ", ".join(names))
    return Signature("judge", judge, message_class(message))
