"""What a user's pytest session prints: a failure leads with the harness's message and
the user's own lines (not the harness's source); a session that collects nothing beside a
rig file or a firmware says how to write the first test; JUnit's artefacts property
resolves from the JUnit file, inside the uploaded folder. Each runs pytest in a process of
its own on a copy of examples/pico_bot in a scratch folder, as a user's repository."""

import os
import re
import shutil
import subprocess
import sys
import textwrap
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from host.core.paths import REPO

PICO = REPO / "examples" / "pico_bot"
SESSION_TIMEOUT_S = 240
FAILING = """\
from host.rig.config.budgets import PeriodBudget


def wait_for_ready(rig):
    rig.expect("never printed", timeout_s=0.3)


def test_the_bot_says_ready(make_rig):
    rig = make_rig("rig.toml", seed=1)
    wait_for_ready(rig)


def test_a_rig_file_that_is_not_there(make_rig):
    make_rig("missing.toml")


def test_a_budget_never_measured():
    PeriodBudget("loop", "probe:loop", period_us=1000, tolerance_us=10).check()


def test_a_keyword_make_rig_does_not_take(make_rig):
    make_rig("rig.toml", nonsense=1)


def test_a_plain_assert_of_the_users():
    x = 1
    assert x == 2


def test_the_bot_loops(make_rig):
    make_rig("rig.toml", seed=1).run_for(3)
"""


def repository(root: Path, files: dict[str, str] | None = None, sub: str = "robot") -> Path:
    """A user's repository at ``root``: pico_bot's firmware and rig file in ``sub``, with
    these files beside them."""
    robot = root / sub
    robot.mkdir(parents=True)
    for name in ("main.py", "rig.toml"):
        shutil.copy(PICO / name, robot / name)
    for name, text in (files or {}).items():
        (robot / name).write_text(textwrap.dedent(text))
    return robot


def pytest_in(folder: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", *args],
        cwd=folder,
        capture_output=True,
        text=True,
        timeout=SESSION_TIMEOUT_S,
        env={**os.environ, "MPLBACKEND": "Agg"},
    )


def failure_sections(stdout: str) -> dict[str, list[str]]:
    """Each failed test's section of the FAILURES block: its lines, blank ones out."""
    block = stdout.split("= FAILURES =", 1)[1].split("short test summary info", 1)[0]
    parts = re.split(r"^_{3,} (\S+) _{3,}$", block, flags=re.M)
    return {name: [line for line in text.splitlines() if line.strip()] for name, text in zip(parts[1::2], parts[2::2])}


@pytest.fixture(scope="module")
def failed_session(tmp_path_factory):
    root = tmp_path_factory.mktemp("user-repo")
    repository(root, {"test_bot.py": FAILING})
    done = pytest_in(root, "--junitxml=build/junit.xml", "--hil-table-full")
    assert done.returncode == 1, done.stdout[-3000:] + done.stderr[-2000:]
    return root, done.stdout


@pytest.mark.hil
def test_a_failed_rig_test_leads_with_the_harness_message_then_the_users_own_lines(failed_session):
    """Before: 20-40 lines of Rig.expect and waits.expect, their source, before the message."""
    _root, out = failed_session
    lines = failure_sections(out)["test_the_bot_says_ready"]
    assert lines[0].startswith("E   ExpectTimeout: expected the console to match 'never printed' within 0.3"), lines
    assert "E   pico_bot: press start" in lines[:6], lines
    user = lines.index(next(line for line in lines if not line.startswith(("E   ", "_ _"))))
    assert lines[user:][:4] == [
        "robot/test_bot.py:10: in test_the_bot_says_ready",
        "    wait_for_ready(rig)",
        "robot/test_bot.py:5: in wait_for_ready",
        '    rig.expect("never printed", timeout_s=0.3)',
    ], lines
    assert lines[user + 4].startswith("----") and "firmware in the loop" in lines[user + 4], lines
    harness = [line for line in lines if re.search(r"host/(rig|pytest_plugin)/|def expect|raise ExpectTimeout", line)]
    assert not harness, harness
    assert "FAILED robot/test_bot.py::test_the_bot_says_ready - ExpectTimeout: expected" in out


@pytest.mark.hil
@pytest.mark.parametrize(
    ("test", "message", "line"),
    [
        ("test_a_rig_file_that_is_not_there", "E   ConfigError: make_rig: no rig file 'missing.toml'", 14),
        ("test_a_budget_never_measured", "E   AssertionError: budget loop: expected measurements of probe:loop", 18),
        ("test_a_keyword_make_rig_does_not_take", "E   TypeError: make_rig: unexpected keywords nonsense", 22),
    ],
)
def test_every_error_the_harness_raises_on_purpose_leads_with_its_message(failed_session, test, message, line):
    lines = failure_sections(failed_session[1])[test]
    assert lines[0].startswith(message), lines
    assert lines[1].startswith("_ _") and lines[2] == f"robot/test_bot.py:{line}: in {test}" and len(lines) == 4, lines


@pytest.mark.hil
def test_a_rig_file_run_as_a_test_leads_with_the_budgets_it_missed(tmp_path):
    """A rig file named to pytest is a test of its budgets: it fails on a budget it misses
    (``pytest rig.toml`` from its folder, as a user runs it), and says which first."""
    robot = repository(tmp_path)
    rig = (robot / "rig.toml").read_text().replace("tolerance_us = 2_000", "tolerance_us = 1")
    (robot / "rig.toml").write_text(rig)
    done = pytest_in(robot, "--hil-rig-seconds", "3", "rig.toml")
    assert done.returncode == 1 and "1 failed" in done.stdout, done.stdout[-3000:]
    (lines,) = failure_sections(done.stdout).values()
    assert lines[0] == f"E   AssertionError: {robot / 'rig.toml'} for 3 s:", lines
    assert lines[1].startswith("E     budget loop: expected every value 50000 +- 1 us"), lines
    assert lines[2].startswith("----") and not [line for line in lines if "assert not" in line or "def " in line]


@pytest.mark.hil
def test_a_users_own_failure_keeps_pytests_report(failed_session):
    lines = failure_sections(failed_session[1])["test_a_plain_assert_of_the_users"]
    assert lines[0].strip() == "def test_a_plain_assert_of_the_users():" and ">       assert x == 2" in lines, lines


@pytest.mark.hil
def test_junits_artefacts_property_is_relative_to_the_junit_file_and_resolves_there(failed_session):
    """Before: an absolute path of the machine that ran it, outside the uploaded folder."""
    root = failed_session[0]
    junit = root / "build" / "junit.xml"
    properties = {
        (case.get("name"), p.get("name")): p.get("value")
        for case in ET.parse(junit).iter("testcase")
        for p in case.iter("property")
    }
    value = properties[("test_the_bot_says_ready", "rig0.artefacts")]
    assert not Path(value).is_absolute(), value
    (kept,) = root.rglob("hil/test_bot/test_the_bot_says_ready/rig0")  # (where the rig wrote)
    assert value == os.path.relpath(kept, junit.parent), value
    assert (junit.parent / value / "console.log").is_file() and (junit.parent / value / "header.json").is_file()


@pytest.mark.hil
def test_hil_table_full_alone_ends_the_session_with_every_budget_of_every_rig(failed_session):
    """Before: --hil-table-full without --hil-table printed nothing."""
    out = failed_session[1]
    table = out.split("= timing budgets (us of virtual time unless marked wall) =", 1)
    assert len(table) == 2, out[-3000:]
    assert re.search(r"^test_the_bot_loops\s+rig0\s+loop\s", table[1], re.M), table[1][:2000]


def test_hil_record_long_without_a_report_is_refused_saying_why(tmp_path):
    """Before: accepted, and it did nothing."""
    done = pytest_in(tmp_path, "--hil-record-long")
    assert done.returncode == 4, done.stdout + done.stderr
    assert "--hil-record-long: expected with --hil-report PATH" in done.stderr, done.stderr


@pytest.mark.parametrize("beside", ["rig file", "firmware"])
def test_a_session_that_collects_nothing_beside_a_rig_file_or_firmware_says_how_to_write_the_first_test(
    tmp_path, beside
):
    """Before: `no tests ran` and nothing else, after the README's quick start."""
    robot = repository(tmp_path, sub="firmware/robot")
    if beside == "firmware":
        (robot / "rig.toml").unlink()
    done = pytest_in(tmp_path)
    assert done.returncode == 5, done.stdout[-2000:]
    out = done.stdout
    if beside == "rig file":
        assert "no test ran; a rig file is here with no test beside it: firmware/robot/rig.toml" in out, out
        assert "def test_robot_keeps_its_budgets(make_rig):" in out and 'make_rig("rig.toml", seed=1)' in out, out
        assert "pytest firmware/robot/rig.toml" in out, out
    else:
        assert "no test ran; a firmware folder is here with no rig file: firmware/robot" in out, out
        assert "mpy-fil init firmware/robot" in out, out
    assert "mpy-fil docs rig-api" in out


def test_a_session_that_collects_nothing_and_has_no_rig_file_or_firmware_adds_nothing(tmp_path):
    (tmp_path / "notes.py").write_text("x = 1\n")
    done = pytest_in(tmp_path)
    assert done.returncode == 5 and "rig" not in done.stdout.split("collected 0 items", 1)[1], done.stdout


def test_tests_deselected_beside_a_rig_file_are_no_missing_first_test(tmp_path):
    repository(tmp_path, {"test_a.py": "def test_a():\n    pass\n"})
    done = pytest_in(tmp_path, "-k", "nothing_matches")
    assert done.returncode == 5 and "deselected" in done.stdout and "first test" not in done.stdout, done.stdout


def test_a_harness_message_with_a_console_line_that_starts_with_assert_is_kept_whole():
    """Only a harness `assert` statement's message loses pytest's explanation after it."""
    from host.pytest_plugin import failure
    from host.rig.loop import waits

    class Rig:
        t_us, seed, artefacts = 0, 1, None

        def run_until(self, t_us):
            self.t_us = t_us

        def where(self):
            return "\nconsole (last 20 lines):\nassert x failed on the board\nseed: 1"

    with pytest.raises(waits.ExpectTimeout) as raised:
        waits.until(Rig(), lambda: False, 0.02)
    assert failure.on_purpose(raised) and not failure._harness_assert(raised)
    assert failure.message_of(raised.value).endswith("assert x failed on the board\nseed: 1")
