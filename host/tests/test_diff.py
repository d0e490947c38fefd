"""mpy-fil diff A B: a one-line change of a firmware's threshold, which still passes its
scenario, is flagged (the robot's path moves, the outputs diverge at a virtual time),
a run and its replay are the same, budgets' changes are judged against thresholds, and
a folder that cannot be read is one line with exit 2."""

import shutil
from pathlib import Path

import pytest

from host.campaign import load_campaign
from host.campaign.worker import run_one
from host.core.paths import REPO
from host.diff.compare import Thresholds, compare_budgets
from host.tests.conftest import run_cli

EXAMPLE = REPO / "examples" / "two_sonar_bot"
CHANGE = ("FRONT_STOP_CM = 30", "FRONT_STOP_CM = 32")


def judged_run(rig: Path, out: Path) -> dict:
    """The rig's campaign run (its declared judge: 'stopped' and no contact), recorded."""
    task = load_campaign(str(rig), seeds=1, seconds=28.0).tasks()[0]
    return run_one(task, str(out), record=True)


@pytest.fixture(scope="module")
def two_versions(tmp_path_factory):
    folder = tmp_path_factory.mktemp("diff")
    changed = folder / "changed"
    shutil.copytree(EXAMPLE, changed, ignore=shutil.ignore_patterns("build", "__pycache__"))
    source = (changed / "main.py").read_text()
    assert source.count(CHANGE[0]) == 1
    (changed / "main.py").write_text(source.replace(*CHANGE))
    a = judged_run(EXAMPLE / "rig.toml", folder / "a")
    b = judged_run(changed / "rig.toml", folder / "b")
    return folder, a, b


def test_a_one_line_threshold_change_that_still_passes_is_flagged(two_versions):
    folder, a, b = two_versions
    assert a["passed"] and b["passed"], (a["message"], b["message"])
    code, text, err = run_cli("diff", a["artefacts"], b["artefacts"], "--out", folder / "plot")
    assert code == 1, err
    position = next(line for line in text.splitlines() if line.startswith("position (m)"))
    max_m, rms_m, at_s = (float(v) for v in position.split()[2:5])
    assert 0.02 < max_m < 0.2 and 0 < rms_m < max_m and 4.0 < at_s < 14.0, position
    motor = next(line for line in text.splitlines() if line.startswith("motor_l.in2"))
    assert "same" not in motor, "the motors reverse at another instant"
    assert "DIFFERS beyond the thresholds: position differs by up to" in text
    plot = folder / "plot" / "diff.png"
    assert f"plot: {plot}" in text and plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    code, text, _ = run_cli("diff", a["artefacts"], b["artefacts"], "--out", folder / "plot", "--max-pos-m", "0.2",
                            "--max-rms-m", "0.2")  # fmt: skip
    assert code == 0 and "same within the thresholds" in text
    code, text, _ = run_cli("diff", a["artefacts"], b["artefacts"], "--out", folder / "plot", "--max-pos-m", "0.2",
                            "--max-rms-m", "0.2", "--fail-on-output")  # fmt: skip
    assert code == 1 and "first differs at t=4." in text and "(--fail-on-output)" in text


def test_a_run_and_its_replay_are_the_same(two_versions, tmp_path):
    folder, a, _ = two_versions
    code, _, err = run_cli("replay", a["artefacts"], "--app", EXAMPLE / "rig.toml", "--out", tmp_path / "replay")
    assert code == 0, err
    code, text, err = run_cli("diff", a["artefacts"], tmp_path / "replay", "--fail-on-output", "--out", tmp_path / "d")
    assert code == 0, text + err
    rows = [line for line in text.splitlines() if line.startswith(("motor_", "led.in", "sonar_"))]
    assert len(rows) == 9 and all(" same" in row for row in rows), rows
    assert "trajectory not compared: B has no ground truth" in text and "same within the thresholds" in text


def test_budget_changes_are_judged_and_wall_clock_budgets_never(two_versions):
    _, a, _ = two_versions

    def budget(name, p99, misses, wall=False):
        return {"name": name, "wall_clock": wall, "stats": {"p50": 10, "p99": p99, "misses": misses}}

    rows = compare_budgets(
        [budget("control.period", 50_000, 0), budget("control.compute", 400, 0, wall=True)],
        [budget("control.period", 51_500, 2), budget("control.compute", 9_000, 5, wall=True)],
    )
    assert rows[0]["p99_change"] == 1500 and rows[0]["misses_change"] == 2
    from host.diff.compare import Diff

    diff = Diff(a=None, b=None, budgets=rows)
    assert diff.beyond(Thresholds(max_misses_change=0)) == [
        "budget control.period misses rose by 2 (--max-misses-change)"
    ]
    assert diff.beyond(Thresholds(max_p99_change_us=2000)) == []
    assert diff.beyond(Thresholds()) == [], "budgets are judged only when a threshold is given"


def test_a_folder_that_cannot_be_read_is_one_line_and_exit_2(two_versions, tmp_path):
    _, a, _ = two_versions
    code, _, err = run_cli("diff", tmp_path, a["artefacts"])
    assert code == 2 and err.count("\n") == 1 and "not a trace folder" in err
    damaged = tmp_path / "damaged"
    shutil.copytree(a["artefacts"], damaged)
    with (damaged / "signals.csv").open("a") as f:
        f.write("1,led.in,1\n")
    code, _, err = run_cli("diff", a["artefacts"], damaged, "--out", tmp_path / "plot")
    assert code == 2 and err.count("\n") == 1 and "signals.csv does not match its digest" in err
    code, _, err = run_cli("diff", a["artefacts"], a["artefacts"], "--max-rms-m", "nan")
    assert code == 2 and err.count("\n") == 1 and "--max-rms-m: expected a number >= 0" in err
