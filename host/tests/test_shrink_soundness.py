"""mpy-fil shrink keeps only candidates that fail as the original did, judged soundly: a
failure a shorter run has whatever the firmware does (a console text the judge wants) never
has its duration cut, so the fixed firmware passes the minimal run; a failure that is the
harness's own (faults it cannot read) is refused, not shrunk; a judge the shrink does not
know is refused; an exception raised by another line is another failure."""

import json
import shutil
from pathlib import Path

import pytest

from host.artefacts.folder import reseal
from host.campaign import load_campaign, replay
from host.campaign.runner import run_campaign
from host.core.errors import ConfigError
from host.shrink.shrinker import Shrinker
from host.shrink.signature import signature
from host.tests.conftest import run_cli

BENCH = Path(__file__).parent / "shrink_bench"
BUGGY = """import time
print("booting")
time.sleep_ms(1000)
print("ERR: calibration")  # (the fixed firmware prints OK here)
while True:
    time.sleep_ms(50)
"""
HARMLESS = '[[faultsets]]\nname = "noisy"\n[[faultsets.faults]]\nkind = "noise"\nsignal = "spare.adc"\nsd = 500.0\n'


@pytest.fixture(scope="module")
def console_judged(tmp_path_factory):
    """The bench with a firmware that prints ERR where it should print OK, judged by
    ``[report.judge] console = "OK"``; a campaign of one 2 s run with a harmless fault."""
    folder = tmp_path_factory.mktemp("console_judged")
    firmware = folder / "firmware"
    firmware.mkdir()
    (firmware / "rig.toml").write_text((BENCH / "rig.toml").read_text() + '\n[report.judge]\nconsole = "OK"\n')
    (firmware / "main.py").write_text(BUGGY)
    (folder / "faults.toml").write_text(HARMLESS)
    campaign = load_campaign(str(firmware / "rig.toml"), faults_file=str(folder / "faults.toml"), seeds=1, seconds=2.0)
    (result,) = run_campaign(campaign, folder / "campaign", workers=1)
    assert not result["passed"] and result["message"] == "expected 'OK' on the console", result
    return folder, firmware, result


def test_a_console_judged_failure_keeps_its_duration_and_the_fixed_firmware_passes_the_minimal_run(console_judged):
    folder, firmware, result = console_judged
    out = folder / "minimal"
    code, text, err = run_cli("shrink", folder / "campaign" / "runs" / result["key"], "--out", out, "--workers", "1")
    assert code == 0, err
    report = json.loads((out / "shrink.json").read_text())
    assert report["minimal"]["seconds"] == 2.0, "a shorter run fails 'expected OK on the console' whatever runs"
    assert report["minimal"]["faults"] == [], "the harmless fault is taken out"
    assert any("duration kept" in note for note in report["notes"]), report["notes"]
    key = report["command"].split("--replay ")[1].split()[0]
    assert signature(replay(out, key), "declared") == signature(result, "declared"), "the buggy one still fails"
    (firmware / "main.py").write_text(BUGGY.replace('"ERR: calibration"', '"OK"'))
    try:
        fixed = replay(out, key)
    finally:
        (firmware / "main.py").write_text(BUGGY)
    assert fixed["passed"], f"the fixed firmware must pass the minimal run: {fixed['message']}"


def test_a_console_judged_failure_with_no_fault_to_take_out_is_refused(console_judged, tmp_path):
    _, firmware, _ = console_judged
    campaign = load_campaign(str(firmware / "rig.toml"), seeds=1, seconds=2.0)
    (result,) = run_campaign(campaign, tmp_path / "campaign", workers=1)
    code, _, err = run_cli("shrink", tmp_path / "campaign" / "runs" / result["key"], "--workers", "1")
    assert code == 2 and err.count("\n") == 1, err
    assert "a shorter run fails so whatever the firmware does" in err and "nothing can be shrunk soundly" in err


@pytest.fixture(scope="module")
def bench_trace(tmp_path_factory):
    out = tmp_path_factory.mktemp("bench_trace") / "run"
    code, _, err = run_cli("run", BENCH / "rig.toml", "--duration", "0.5", "--out", out)
    assert code == 0, err
    return out


@pytest.mark.parametrize(
    ("faults", "expected"),
    [
        ([{"kind": "teleport"}], "header.json spec.faults[0] kind: expected one of"),
        ([{"kind": "stuck", "signal": "batt.adc"}], "header.json spec.faults[0] (stuck): missing value"),
        ({"kind": "stuck"}, "header.json spec.faults: expected an array of tables"),
        ([{"kind": "stuck", "signal": "nowhere.adc", "value": 1}], "the harness's own error, not the firmware's"),
    ],
)
def test_a_trace_folder_whose_faults_the_harness_cannot_apply_is_refused_not_shrunk(
    bench_trace, tmp_path, faults, expected
):
    trace = tmp_path / "trace"
    shutil.copytree(bench_trace, trace)
    header = json.loads((trace / "header.json").read_text())
    header["spec"]["faults"] = faults
    (trace / "header.json").write_text(json.dumps(header))
    reseal(trace)
    code, text, err = run_cli("shrink", trace, "--app", BENCH / "rig.toml", "--workers", "1", "--out", tmp_path / "o")
    assert code == 2 and expected in err and err.count("\n") == 1, (code, err)
    assert "shrink faults:" not in text, "nothing was shrunk"


def test_a_judge_the_shrink_does_not_know_is_refused_before_any_run():
    task = {"judge": "mystery", "faults": [], "seconds": 1.0}
    with pytest.raises(ConfigError, match="judge 'mystery': a shrink knows only the judges"):
        Shrinker(task, runs=None).shrink()


def test_the_same_exception_raised_by_another_line_is_another_failure():
    def raised(line: int) -> dict:
        message = (
            "FirmwareError: firmware raised at virtual t=1.5 s\nMicroPython traceback:\n"
            f'Traceback (most recent call last):\n  File "main.py", line {line}, in <module>\n'
            "AssertionError: \n"
        )
        return {"passed": False, "error": "FirmwareError", "message": message}

    assert signature(raised(40), "generic") == signature(raised(40), "generic")
    assert signature(raised(40), "generic") != signature(raised(80), "generic")
    assert signature(raised(40), "generic").message_class.endswith("| AssertionError: @ main.py:40")


def test_campaign_shrink_says_a_refused_failure_and_goes_on(console_judged, tmp_path):
    from host.shrink.command import shrink_campaign

    _, firmware, _ = console_judged
    campaign = load_campaign(str(firmware / "rig.toml"), seeds=1, seconds=2.0)
    results = run_campaign(campaign, tmp_path / "campaign", workers=1)
    said = []
    rows = shrink_campaign(campaign, results, tmp_path / "campaign", workers=1, say=said.append)
    assert len(rows) == 1 and "nothing can be shrunk soundly" in rows[0]["refused"], rows
    assert any("shrink 1 of 1: refused:" in line for line in said), said
