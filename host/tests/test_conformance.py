"""MicroPython's own tests in the loop (make conformance; here a few of each kind)."""

import subprocess
import sys

import pytest

from host.conformance.__main__ import OUT, SUBSET, known, verdict

pytestmark = pytest.mark.hil


def test_upstreams_tests_pass_in_the_loop_as_on_the_plain_port():
    proc = subprocess.run(
        [sys.executable, "-m", "host.conformance", "--subset"], capture_output=True, text=True, timeout=600
    )
    assert proc.returncode == 0, (
        f"expected every subset test to pass in the loop:\n{proc.stdout}\n{proc.stderr}\n(logs: {OUT})"
    )
    for test in SUBSET:
        row = next(line for line in proc.stdout.splitlines() if f"`{test}`" in line)
        assert row.split("|")[3].strip() == "pass", row


def test_the_verdict_names_an_unlisted_failure_and_a_stale_listing():
    files = ["a.py", "b.py", "c.py"]
    plain = {"a.py": "pass", "b.py": "pass", "c.py": "pass"}
    shim = {"a.py": "FAIL", "b.py": "pass", "c.py": "FAIL"}
    problems = verdict(files, plain, shim, {"b.py": "why", "c.py": "why"}, {})
    assert len(problems) == 2
    assert problems[0].startswith("a.py: passes on the plain port, FAIL in the loop")
    assert problems[1].startswith("b.py: listed in host/conformance/known.toml but passes")


def test_every_known_difference_gives_its_reason():
    for name, reason in known().items():
        assert len(reason) > 40, f"{name}: a reason that says why, on a board too"
