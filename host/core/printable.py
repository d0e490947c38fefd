"""Text from the firmware as the harness prints it: inert on any terminal.

A firmware prints what it likes: an ESC sequence that sets a terminal's title, writes
its clipboard (OSC 52), moves the cursor or clears a line, a carriage return that
overwrites the line before it in a CI log, a NUL, a bell. The harness prints the
firmware's words (its console's last lines, a traceback in an error, a line a scenario
or an ``expect`` waited for) through :func:`printable` alone: every C0 and C1 control
character but the newline and the tab, and DEL, is shown as its escape (``\\x1b``,
``\\r``), so the sequence shows as text and does nothing. ``console.log`` keeps the
bytes as they came (:mod:`host.artefacts.console`): the file is the record, the
terminal a view of it.
"""

import re

CONTROLS = re.compile(r"[\x00-\x08\x0b-\x1f\x7f-\x9f]")
"""C0 (but ``\\t`` and ``\\n``), DEL and C1: what a terminal acts on rather than shows."""
NAMED = {"\r": "\\r", "\b": "\\b", "\f": "\\f", "\v": "\\v"}


def _escape(match: re.Match) -> str:
    char = match.group()
    return NAMED.get(char) or f"\\x{ord(char):02x}"


def printable(text) -> str:
    """``text`` (str or bytes, bytes read as UTF-8 with replacement) with every control
    character a terminal would act on shown as its escape; newlines and tabs kept."""
    if isinstance(text, (bytes, bytearray)):
        text = bytes(text).decode("utf-8", errors="replace")
    return CONTROLS.sub(_escape, str(text))
