"""The shim's clock in real-time pacing: the board's ticks less the host's pauses
(docs/clock.md). A pause the host measured longer than the board's clock saw it once took
the clock back, below zero at the start: a CFG then carried a negative instant, packed
unsigned (2**64 - 839 us), and the host's plant was asked to advance to it (a virtual
board killed by a ZeroDivisionError in an encoder with no next edge)."""

import subprocess

from host.core import interpreter
from host.core.paths import SHIM_DIR

_CLOCK = """
import sys
sys.path.insert(0, %r)
import _hil
rt = _hil._rtime
_hil._now = 500
_hil._rt_origin_us = rt.ticks_add(rt.ticks_us(), 10000)  # a pause 10 ms longer than seen
held = _hil._realtime_now()
rt.sleep_ms(15)
later = _hil._realtime_now()
print(held, later)
"""


def test_a_pause_longer_than_the_board_saw_holds_the_clock_instead_of_taking_it_back():
    out = subprocess.run(
        [str(interpreter.find()), "-c", _CLOCK % str(SHIM_DIR)], capture_output=True, text=True, timeout=30
    )
    assert out.returncode == 0, out.stderr
    held, later = map(int, out.stdout.split())
    assert held == 500, f"expected the clock held at its last instant (500 us), got {held} us"
    assert later > 500, f"expected the clock to go on once the board's ticks pass the pause, got {later} us"
