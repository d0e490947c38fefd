"""mpy-fil shrink: delta debugging finds the minimal fault set (a property over planted
sets), a failure signature tells one failure from another, and a planted failure on a
small bench firmware (host/tests/shrink_bench: only a stuck battery inside a window of
its clock matters) shrinks to that one fault, a window around that instant and a shorter
run, which the printed command runs again to the same failure; campaign --shrink shrinks
each distinct failure of a campaign on its process pool to the same answer."""

import json
import shutil
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from host.campaign import load_campaign, replay
from host.campaign.runner import run_campaign
from host.shrink.ddmin import ddmin
from host.shrink.signature import Signature, message_class, signature
from host.tests.conftest import run_cli

BENCH = Path(__file__).parent / "shrink_bench" / "rig.toml"
STUCK_BATT = {"kind": "stuck", "signal": "batt.adc", "value": 1000}
STUCK_SPARE = {"kind": "stuck", "signal": "spare.adc", "value": 3}
HARMLESS = [
    {"kind": "noise", "signal": "spare.adc", "sd": 500.0},
    {"kind": "dropout", "signal": "btn.out", "start_s": 0.4, "end_s": 0.9},
    {"kind": "stuck", "signal": "spare.adc", "value": 40000},
    {"kind": "noise", "signal": "batt.adc", "sd": 20.0},
]
FAULTS_TOML = """
[[faultsets]]
name = "one-matters"
{one}
[[faultsets]]
name = "spare-first"
{spare}
[[faultsets]]
name = "fine"
{fine}
"""


def toml_faults(faults: list[dict]) -> str:
    def value(v):
        return f'"{v}"' if isinstance(v, str) else repr(v)

    return "\n".join("[[faultsets.faults]]\n" + "\n".join(f"{k} = {value(v)}" for k, v in f.items()) for f in faults)


# -- delta debugging and the signature --------------------------------------------


@settings(max_examples=200, deadline=None, database=None)
@given(data=st.data(), n=st.integers(1, 24))
def test_ddmin_finds_exactly_the_faults_that_matter_among_ones_that_do_not(data, n):
    needed = data.draw(st.sets(st.integers(0, n - 1), min_size=1, max_size=min(n, 4)))
    tried = set()  # (a shrink runs each distinct candidate once: host.shrink.runs keeps results)

    def fails(candidates):
        tried.update(tuple(c) for c in candidates)
        return [needed <= set(c) for c in candidates]

    assert ddmin(list(range(n)), fails) == sorted(needed)
    assert len(tried) <= n * n + 3 * n, "ddmin's worst case: quadratic in the faults"
    if len(needed) == 1:
        assert len(tried) <= 2 * n.bit_length() + 2, "one fault that matters: found by halving"


def test_ddmin_keeps_nothing_when_the_run_fails_without_any_fault():
    assert ddmin([0, 1, 2], lambda cs: [True] * len(cs)) == []


def test_a_signature_keeps_the_kind_of_failure_and_drops_the_numbers():
    a = {"passed": False, "error": None, "message": "expected home within 150 mm, got 289 mm off"}
    b = {"passed": False, "error": None, "message": "expected home within 150 mm, got 227 mm off"}
    c = {"passed": False, "error": None, "message": "expected one branch and two ends explored, got ''"}
    assert signature(a, "duct_branch") == signature(b, "duct_branch") != signature(c, "duct_branch")
    assert signature({"passed": True}, "generic") is None
    assert signature(a, "duct_branch") != signature(a, "declared"), "another judge is another failure"
    raised = "FirmwareError: firmware raised at virtual t=1.5 s; expected it to keep running.\nMicroPython traceback:"
    run = {"passed": False, "error": "FirmwareError", "message": raised + "\n  File x\nRuntimeError: low 7 at 3"}
    other = {**run, "message": raised + "\n  File x\nValueError: spare low at 1000 ms"}
    assert signature(run, "generic") == Signature(
        "error",
        "FirmwareError",
        "firmware raised at virtual t=# s; expected it to keep running. | RuntimeError: low # at #",
    )
    assert signature(run, "generic") != signature(other, "generic"), "another exception is another failure"
    budgets = {
        "passed": False,
        "error": None,
        "message": "expected the budgets kept, missed: b.two (3 misses), a.one (1 misses)",
    }
    assert signature(budgets, "generic") == Signature("budget", "budgets", "a.one, b.two")
    deadline = {"passed": False, "error": None, "message": "expected 'done:' within 75 simulated min"}
    assert signature(deadline, "pool_mission").deadline and not signature(a, "duct_branch").deadline
    assert message_class("got 0x1f and -3.5e-2, 12%  ok") == "got # and #, #% ok"


# -- planted failures on a small firmware ----------------------------------------------


@pytest.fixture(scope="module")
def campaign_folder(tmp_path_factory):
    """A campaign of the bench, one seed, 4 s: one fault that matters among four that do
    not; a stuck spare (the earlier failure) with a stuck main battery; harmless faults."""
    folder = tmp_path_factory.mktemp("shrink")
    faults = folder / "faults.toml"
    faults.write_text(
        FAULTS_TOML.format(
            one=toml_faults(HARMLESS[:2] + [STUCK_BATT] + HARMLESS[2:]),
            spare=toml_faults([STUCK_BATT, HARMLESS[0], STUCK_SPARE]),
            fine=toml_faults(HARMLESS),
        )
    )
    campaign = load_campaign(str(BENCH), faults_file=str(faults), seeds=1, seconds=4.0)
    results = {r["key"]: r for r in run_campaign(campaign, folder / "campaign", workers=1)}
    assert [k for k, r in results.items() if r["passed"]] == ["fine/default/1"]
    return folder, campaign


def test_a_fault_that_matters_only_inside_a_window_shrinks_to_it_and_replays(campaign_folder):
    folder, _ = campaign_folder
    out = folder / "minimal"
    code, text, err = run_cli(
        "shrink", str(folder / "campaign/runs/one-matters/default/1"), "--out", str(out), "--workers", "1"
    )
    assert code == 0, err
    report = json.loads((out / "shrink.json").read_text())
    minimal = report["minimal"]
    (fault,) = minimal["faults"]
    assert {k: fault[k] for k in STUCK_BATT} == STUCK_BATT, "only the stuck main battery is left"
    resolution_s = 4.0 / 64
    assert fault["end_s"] - fault["start_s"] <= resolution_s + 1e-9
    assert 1.4 <= fault["start_s"] < 2.0, "a window where the firmware reads a sample in its 1.5-2.0 s check"
    assert 1.5 <= minimal["seconds"] <= 2.0 + resolution_s, "the run ends soon after the failure"
    assert report["signature"]["message_class"].endswith("| RuntimeError: battery low: # at # ms @ main.py:21")
    assert [r["after"] for r in report["removed"]][:5] == [
        "removed",
        "removed",
        f"{fault['start_s']:g}-{fault['end_s']:g} s",
        "removed",
        "removed",
    ]
    assert "what" in text and "faults[2] stuck batt.adc" in text and "shrink faults:" in text
    command = report["command"]
    assert f"run it again (traced): {command}" in text
    key = command.split("--replay ")[1].split()[0]
    again = replay(out, key)
    assert signature(again, minimal["judge"]) == Signature(**report["signature"])
    assert (out / "replay" / key / "header.json").is_file(), "the command leaves a trace folder"
    assert report["runs"] < 60


def test_a_fault_whose_removal_changes_the_failure_is_kept(campaign_folder):
    """The stuck spare fails first (ValueError at 1.0 s); without it the stuck main battery
    fails too, but as a RuntimeError: not the same failure, so the spare is what is left."""
    folder, _ = campaign_folder
    out = folder / "spare"
    code, _, err = run_cli(
        "shrink", str(folder / "campaign/spare-first/default/1"), "--out", str(out), "--workers", "1"
    )
    assert code == 0, err
    report = json.loads((out / "shrink.json").read_text())
    assert [f["signal"] for f in report["minimal"]["faults"]] == ["spare.adc"]
    assert "ValueError: spare battery low" in report["signature"]["message_class"]


def test_campaign_shrink_shrinks_each_distinct_failure_on_the_pool_to_the_same_answer(campaign_folder):
    folder, _ = campaign_folder
    args = ["--seeds", "1", "--seconds", "4", "--workers", "2", "--out", str(folder / "campaign"), "--shrink"]
    code, text, err = run_cli("campaign", str(BENCH), "--faults", str(folder / "faults.toml"), *args)
    assert code == 0, err
    assert "shrink 1 of 2: one-matters/default/1" in text and "shrink 2 of 2: spare-first/default/1" in text
    pooled = json.loads((folder / "campaign/shrink/1/shrink.json").read_text())["minimal"]
    alone_out = folder / "alone"
    run_cli("shrink", str(folder / "campaign/runs/one-matters/default/1"), "--out", str(alone_out), "--workers", "1")
    alone = json.loads((alone_out / "shrink.json").read_text())["minimal"]
    assert pooled == alone, "two workers find the same minimal run as one"


def test_a_passing_run_or_a_folder_that_is_no_run_is_refused_in_one_line(campaign_folder, tmp_path):
    folder, _ = campaign_folder
    code, _, err = run_cli(
        "shrink", str(folder / "campaign/fine/default/1"), "--out", str(tmp_path / "x"), "--workers", "1"
    )
    assert code == 2 and err.count("\n") == 1 and "the run passed when run again: nothing to shrink" in err
    code, _, err = run_cli("shrink", str(tmp_path), "--workers", "1")
    assert code == 2 and err.count("\n") == 1 and "expected a trace folder" in err


def test_a_trace_folder_outside_a_campaign_shrinks_from_its_header(campaign_folder, tmp_path):
    """A recorded run's folder alone: its header's rig, seed and faults, its duration; the
    rig file it names is run only when the user says so."""
    folder, _ = campaign_folder
    result = replay(folder / "campaign", "one-matters/default/1")
    trace = tmp_path / "trace"
    shutil.copytree(result["artefacts"], trace)
    code, _, err = run_cli("shrink", trace, "--workers", "1", "--out", tmp_path / "out")
    assert code == 2 and "--trust-folder" in err and err.count("\n") == 1
    code, text, err = run_cli("shrink", trace, "--workers", "1", "--out", tmp_path / "out", "--trust-folder")
    assert code == 0, err
    minimal = json.loads((tmp_path / "out" / "shrink.json").read_text())["minimal"]
    assert [(f["kind"], f["signal"]) for f in minimal["faults"]] == [("stuck", "batt.adc")]
    recorded_s = json.loads((trace / "header.json").read_text())["t_end_us"] / 1e6
    assert minimal["faultset"] == "trace" and 1.5 <= minimal["seconds"] <= recorded_s, "no longer than the recording"
