"""A test's own budget limits: ``@pytest.mark.hil_budget(name, max_ms=...)`` and
``make_rig(..., budget_limits=...)``, in a pytest session of their own: a limit tighter
than the run fails the test with the budget's usual message, a looser one lets it pass
and shows in the JUnit properties, and a name or a key the rig does not know is an error
that says what there is."""

import subprocess
import sys
import textwrap
import xml.etree.ElementTree as ET

import pytest

from host.core.paths import REPO

pytestmark = [pytest.mark.hil, pytest.mark.xdist_group("test_budget_marks")]  # (make hil: its module fixtures run once)

SESSION_TIMEOUT_S = 120
SCENARIOS = """
    import pytest


    @pytest.mark.hil_budget("sonar.latency", max_us=100)
    def test_tight(make_rig):
        rig = make_rig("rover", seed=1)
        rig.run_for(3)
        rig.budgets["sonar.latency"].check()


    @pytest.mark.hil_budget("sonar.latency", max_ms=1)
    def test_loose(make_rig):
        rig = make_rig("rover", seed=1, budget_limits={"sonar.latency": {"max_ms": 60}})
        rig.run_for(3)
        rig.budgets["sonar.latency"].check()


    @pytest.mark.hil_budget("control.period", tolerance_us=0)
    def test_period_band(make_rig):
        rig = make_rig("rover", seed=1)
        rig.run_for(3)
        rig.budgets["control.period"].check()


    @pytest.mark.hil_budget("control.perod", max_ms=60)
    def test_unknown_name(make_rig):
        make_rig("rover", seed=1)


    @pytest.mark.hil_budget("control.period", maximum_ms=60)
    def test_unknown_key(make_rig):
        make_rig("rover", seed=1)


    @pytest.mark.hil_budget("command", max_ms=2)
    def test_boards_tight(make_boards):
        boards = make_boards("reaction/rig.toml", seed=1)
        boards.run_for(0.2)
        boards.budgets["command"].check()


    @pytest.mark.hil_budget("command", max_ms=2)
    def test_boards_loose(make_boards):
        boards = make_boards("reaction/rig.toml", seed=1, budget_limits={"command": {"max_ms": 6}})
        boards.run_for(0.2)
        boards.budgets["command"].check()


    @pytest.mark.hil_budget("motor:speed_loop", tolerance_us=0)
    def test_boards_own_band(make_boards):
        boards = make_boards(TWO_BOARD_ROVER, seed=1)
        boards.run_for(0.5)
        boards["motor"].budgets["speed_loop"].check()


    @pytest.mark.hil_budget("motor:speed_lop", max_ms=25)
    def test_boards_unknown_name(make_boards):
        make_boards(TWO_BOARD_ROVER, seed=1)
"""
REACTION_RIG = """\
name = "reaction"
[plant]
body = "bench"
[[plant.parts]]
kind = "wire"
name = "cmd"
[[boards]]
name = "left"
firmware = { dir = "left" }
board = { family = "esp32", pins = { CMD = 4 } }
wiring = { CMD = "cmd.in" }
[[boards]]
name = "right"
firmware = { dir = "right" }
board = { family = "rpi_pico", pins = { CMD = 5, ACK = 6 } }
wiring = { CMD = "cmd.out", ACK = "probe:ack" }
[budgets.command]
kind = "reaction"
stimulus = "left:cmd.in"
response = "right:probe:ack"
limit_us = 5000
"""
COMMANDER = """\
import time
from machine import Pin
cmd = Pin(4, Pin.OUT, value=0)
while True:
    time.sleep_ms(20)
    cmd.toggle()
"""
ACTOR = """\
import time
from machine import Pin
ack = Pin(6, Pin.OUT, value=0)
cmd = Pin(5, Pin.IN)
seen = 0
while True:
    time.sleep_ms(1)
    if cmd.value() != seen:
        seen = cmd.value()
        time.sleep_us(3000)  # (the command's work: 3 ms, acted on within 4)
        ack.toggle()
"""


@pytest.fixture(scope="module")
def session(tmp_path_factory):
    where = tmp_path_factory.mktemp("budget_marks")
    rover = REPO / "examples" / "two_board_rover" / "rig.toml"
    scenarios = textwrap.dedent(SCENARIOS).replace("TWO_BOARD_ROVER", repr(str(rover)))
    (where / "test_budget_marks_scenarios.py").write_text(scenarios)
    for path, text in (("rig.toml", REACTION_RIG), ("left/main.py", COMMANDER), ("right/main.py", ACTOR)):
        (where / "reaction" / path).parent.mkdir(parents=True, exist_ok=True)
        (where / "reaction" / path).write_text(text)
    done = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-rA", "-p", "no:cacheprovider", "--strict-markers"]
        + [f"--junitxml={where / 'junit.xml'}", "test_budget_marks_scenarios.py"],
        cwd=where,
        capture_output=True,
        text=True,
        timeout=SESSION_TIMEOUT_S,
    )
    return where, done


def outcome(done, name: str) -> str:
    lines = [line for line in done.stdout.splitlines() if line.endswith(f"::{name}") or f"::{name} - " in line]
    return lines[-1].split()[0] if lines else "(not in the summary)"


def test_a_limit_tighter_than_the_run_fails_the_test_with_the_budgets_usual_message(session):
    _, done = session
    assert outcome(done, "test_tight") == "FAILED", done.stdout[-3000:]
    assert "budget sonar.latency: expected every value <= 100 us, got" in done.stdout, done.stdout[-3000:]
    assert "the first: " in done.stdout and "at virtual t=" in done.stdout, done.stdout[-3000:]


def test_make_rigs_argument_outranks_the_mark_and_the_limit_shows_in_junit(session):
    where, done = session
    assert outcome(done, "test_loose") == "PASSED", done.stdout[-3000:]
    assert outcome(done, "test_period_band") == "PASSED", done.stdout[-3000:]  # lockstep: exactly 50 ms
    cases = {c.get("name"): c for c in ET.parse(where / "junit.xml").iter("testcase")}
    props = {p.get("name"): p.get("value") for p in cases["test_loose"].iter("property")}
    assert props["rig0.budget.sonar.latency"].endswith("limit=<= 60000 us"), props
    props = {p.get("name"): p.get("value") for p in cases["test_period_band"].iter("property")}
    assert props["rig0.budget.control.period"].endswith("limit=50000 +- 0 us"), props


def test_a_budget_the_rig_has_not_or_an_unknown_limit_is_an_error_that_lists_what_there_is(session):
    _, done = session
    assert outcome(done, "test_unknown_name") == "FAILED", done.stdout[-3000:]
    named = "@pytest.mark.hil_budget: no budget 'control.perod' on the rover rig (its budgets: control.compute, "
    assert named + "control.period, sonar.latency, sonar.period)" in done.stdout, done.stdout[-3000:]
    assert outcome(done, "test_unknown_key") == "ERROR", done.stdout[-3000:]
    assert "unknown limit 'maximum_ms'; expected max_ms, max_us, tolerance_ms or tolerance_us" in done.stdout
    assert done.returncode == 1, f"expected exit 1 (tests failed), got {done.returncode}: {done.stderr[-2000:]}"


def test_a_set_of_boards_takes_the_marks_for_its_budgets_across_boards_and_each_boards_own(session):
    """make_boards (docs/multi-board.md): a budget across boards by its name, a board's own
    as <board>:<name>; each in the JUnit properties (boards<n>.budget.<name>, and
    boards<n>.<board>.budget.<name> as a rig's)."""
    where, done = session
    assert outcome(done, "test_boards_tight") == "FAILED", done.stdout[-3000:]
    assert "budget command: expected every value left:cmd.in -> right:probe:ack <= 2000 us" in done.stdout
    assert outcome(done, "test_boards_loose") == "PASSED", done.stdout[-3000:]  # (its argument outranks the mark)
    assert outcome(done, "test_boards_own_band") == "PASSED", done.stdout[-3000:]  # lockstep: exactly 20 ms
    cases = {c.get("name"): c for c in ET.parse(where / "junit.xml").iter("testcase")}
    props = {p.get("name"): p.get("value") for p in cases["test_boards_loose"].iter("property")}
    assert props["boards0.budget.command"].endswith("limit=left:cmd.in -> right:probe:ack <= 6000 us"), props
    props = {p.get("name"): p.get("value") for p in cases["test_boards_own_band"].iter("property")}
    assert props["boards0.motor.budget.speed_loop"].endswith("limit=20000 +- 0 us"), props
    assert outcome(done, "test_boards_unknown_name") == "FAILED", done.stdout[-3000:]
    named = "@pytest.mark.hil_budget: no budget 'motor:speed_lop' on the two_board_rover boards (their budgets: "
    assert named + "motor:speed_loop; a board's own as <board>:<name>)" in done.stdout, done.stdout[-3000:]
