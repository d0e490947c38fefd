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
"""


@pytest.fixture(scope="module")
def session(tmp_path_factory):
    where = tmp_path_factory.mktemp("budget_marks")
    (where / "test_budget_marks_scenarios.py").write_text(textwrap.dedent(SCENARIOS))
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
