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
traceback: ``firmware raised at virtual t=# s; ... | RuntimeError: battery low: # at # ms``
(a ``ValueError`` raised at the same instant is another failure). A passing run has no
signature (None).
"""

import re
from typing import NamedTuple

NUMBER = re.compile(r"[-+]?(?:0x[0-9a-fA-F]+|(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)")
DEADLINE = re.compile(r"\bwithin # (?:s|simulated min)\b")
"""The judges' wording for "the run ended before it got there" (judges.py)."""
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
    for line in lines[lines.index(TRACEBACK) + 1 :]:
        if line.strip() and not line.startswith((" ", "\t", "Traceback")):
            return message_class(line)
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
