"""MicroPython's own tests in the loop, every file of make conformance: a test of
``machine``, ``time``, ``select`` or ``asyncio`` that passes on the plain unix port and
fails in the loop fails here, unless host/conformance/known.toml gives its reason."""

import re
import subprocess
import sys

import pytest

from host.conformance import __main__ as conformance
from host.conformance.__main__ import OUT, known, verdict

pytestmark = pytest.mark.hil

TIMEOUT_S = 900  # the whole set takes about a minute on 2 cores


def rows(table: str) -> dict[str, tuple[str, str]]:
    """The main table's rows: file -> (plain port, in the loop)."""
    out = {}
    for line in table.splitlines():
        m = re.match(r"^\| `([^`]+)` \| (pass|skip|FAIL|error) \| (pass|skip|FAIL|error) \|", line)
        if m:
            out[m.group(1)] = (m.group(2), m.group(3))
    return out


def test_every_file_that_passes_on_the_plain_port_passes_in_the_loop():
    proc = subprocess.run([sys.executable, "-m", "host.conformance"], capture_output=True, text=True, timeout=TIMEOUT_S)
    assert proc.returncode == 0, (
        f"expected every file that passes on the plain port to pass in the loop (or be listed in "
        f"host/conformance/known.toml):\n{proc.stdout}\n{proc.stderr}\n(logs: {OUT})"
    )
    files, _ = conformance.select(conformance.tests_dir())  # (a module's name: tests_dir is no test)
    got = rows(proc.stdout)
    assert set(files) <= set(got), f"expected a row for every file: missing {sorted(set(files) - set(got))}"
    assert len(files) >= 50, f"expected the whole set (51 files in 1.25), got {len(files)}"
    reasons = known()
    regressions = [f for f in files if got[f] == ("pass", "FAIL") or got[f] == ("pass", "error")]
    assert all(f in reasons for f in regressions), f"unlisted failures in the loop: {regressions}"
    assert got["extmod/asyncio_heaplock.py"] == ("pass", "pass"), "asyncio with the heap locked"


def test_the_verdict_names_an_unlisted_failure_and_a_stale_listing():
    files = ["a.py", "b.py", "c.py"]
    plain = {"a.py": "pass", "b.py": "pass", "c.py": "pass"}
    shim = {"a.py": "FAIL", "b.py": "pass", "c.py": "FAIL"}
    problems = verdict(files, plain, shim, {"b.py": "why", "c.py": "why"}, {})
    assert len(problems) == 2
    assert problems[0].startswith("a.py: passes on the plain port, FAIL in the loop")
    assert problems[1].startswith("b.py: listed in host/conformance/known.toml but passes")


def test_an_error_in_the_loop_where_the_plain_port_passes_is_a_failure_too():
    problems = verdict(["a.py"], {"a.py": "pass"}, {"a.py": "error"}, {}, {})
    assert problems and problems[0].startswith("a.py: passes on the plain port, error in the loop"), problems


def test_every_known_difference_gives_its_reason():
    for name, reason in known().items():
        assert len(reason) > 40, f"{name}: a reason that says why, on a board too"


def test_a_known_row_with_versions_holds_for_those_versions_only():
    """Each version's run checks against its own rows (docs/versions.md): a row with
    ``versions`` is that version's; a row without, every version's."""
    every = {"extmod/select_poll_eintr.py", "extmod_hardware/machine_uart_irq_break.py"}
    for version in ("1.25", "1.26", "1.27", "1.28"):
        assert every <= set(known(version)), f"{version}: expected the rows of every version"
    assert {"extmod/machine_timer.py", "extmod/select_poll_basic.py"}.isdisjoint(known("1.25")), known("1.25")
    assert "extmod/machine_timer.py" not in known("1.26"), "1.26 has no hard Timers: its own test skips"
    assert {"extmod/machine_timer.py", "extmod/select_poll_basic.py"} <= set(known("1.28")), known("1.28")
    spi = "extmod/machine_spi_rate.py"  # (1.28's takes its SPIs from the bench's target_wiring)
    assert spi in known("1.27") and spi not in known("1.28"), "expected the SPI rate row up to 1.27"
