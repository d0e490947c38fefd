"""Waiting in virtual time for what a test looks for, as pytest-embedded's
``dut.expect`` and Renode's "Wait For Line On Uart" do: the console matching a pattern,
or a condition on the rig becoming true, within a simulated timeout."""

import re

from host.core.errors import HarnessError
from host.core.printable import printable
from host.rig.config import arguments

STEP_S = 0.01  # simulated seconds between two looks


class ExpectTimeout(HarnessError, AssertionError):
    """What a test waited for did not come within its simulated timeout."""


def expect(rig, pattern, timeout_s: float, step_s: float = STEP_S, advance=None) -> re.Match:
    """Run until the console, past what earlier expects took, matches ``pattern``; the
    match (the console after its end is what the next expect looks at). ``advance(t_us)``
    runs the rig (default ``rig.run_until``: a live rig's journals each stop, host/live)."""
    advance = advance or rig.run_until
    regex = re.compile(pattern) if isinstance(pattern, (str, bytes)) else pattern
    arguments.seconds("expect timeout_s", timeout_s, limit_s=arguments.MAX_RUN_S)
    deadline = rig.t_us + round(timeout_s * 1e6)
    while True:
        text, start = rig.console_log.since(rig.expect_from)
        found = regex.search(text)
        if found is not None:
            rig.expect_from = start + len(text[: found.end()].encode())
            return found
        if rig.t_us >= deadline or rig.exit_kind is not None:
            break
        advance(min(deadline, rig.t_us + round(step_s * 1e6)))
    tail = printable("\n".join(text.rstrip().splitlines()[-20:])) or "(nothing)"
    raise ExpectTimeout(
        f"expected the console to match {printable(repr(regex.pattern))} within {timeout_s:g} simulated s "
        f"(until virtual t={deadline / 1e6:.6f} s); it did not. Console since the last match:\n{tail}"
        f"\nseed: {rig.seed}" + (f"\nartefacts: {rig.artefacts}" if rig.artefacts else "")
    )


def until(rig, predicate, timeout_s: float | None, step_s: float = STEP_S, advance=None):
    """Run until ``predicate()`` is true (its value back), at most ``timeout_s`` simulated s
    (``advance`` as for :func:`expect`)."""
    advance = advance or rig.run_until
    timeout_s = arguments.seconds(
        "run_until timeout_s", 10.0 if timeout_s is None else timeout_s, limit_s=arguments.MAX_RUN_S
    )
    deadline = rig.t_us + round(timeout_s * 1e6)
    while True:
        value = predicate()
        if value:
            return value
        if rig.t_us >= deadline:
            break
        advance(min(deadline, rig.t_us + round(step_s * 1e6)))
    name = getattr(predicate, "__name__", repr(predicate))
    raise ExpectTimeout(
        f"expected {name} to become true within {timeout_s:g} simulated s (until virtual t={deadline / 1e6:.6f} s); "
        f"it did not.{rig.where()}"
    )
